/// The front end's imperfections (front_end.hpp) as a sample stage: one
/// FrontEnd per node on the stage's side, each with its own random streams.
#include <memory>
#include <vector>

#include "rfsitl/channel/front_end.hpp"
#include "rfsitl/channel/sample_stage.hpp"

namespace rfsitl::channel {
namespace {

class ImpairmentsStage final : public SampleStage {
 public:
  ImpairmentsStage(const FrontEndSettings& s, const SampleStageContext& c) {
    const FrontEndSide side =
        c.side == SampleSide::kTransmit ? FrontEndSide::kTransmit : FrontEndSide::kReceive;
    fronts_.reserve(c.nodes);
    for (std::size_t n = 0; n < c.nodes; ++n) {
      fronts_.emplace_back(s, side, c.sample_rate_hz, c.tick_samples, c.seed, c.stream(n));
    }
  }

  // The phase noise's value at tick boundaries is a walk over every tick
  // (front_end.hpp), so it advances whether or not anything is applied.
  void advance(SampleTime tick_start, bool /*applies*/) override {
    for (FrontEnd& f : fronts_) f.advance(tick_start);
  }

  void apply(std::size_t node, SampleTime first_sample, std::span<cf32> x) const override {
    fronts_[node].apply(first_sample, x);
  }

 private:
  std::vector<FrontEnd> fronts_;
};

}  // namespace

SampleStageComponent impairments_component() {
  return {front_end_info(), [](const config::Settings& s, const SampleStageContext& c) {
            return std::make_unique<ImpairmentsStage>(front_end_fields().build(s), c);
          }};
}

}  // namespace rfsitl::channel
