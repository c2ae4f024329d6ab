#pragma once
/// The receivers' thermal noise as the first receive sample stage: each
/// receiver's own counter-based stream (noise_source.hpp: stream m under the
/// scenario's seed), or with shared_noise the paper's one stream for all of
/// them, drawn once per tick when some receiver runs. In the front end's units
/// the noise has power `unit_variance` (1 after the front end's gain).
/// Built by the channel from channel.noise_*, not registered by name: every
/// receiver has it, and its level is the link budget's.
#include <optional>
#include <vector>

#include "rfsitl/channel/noise_source.hpp"
#include "rfsitl/channel/sample_stage.hpp"

namespace rfsitl::channel {

class NoiseStage final : public SampleStage {
 public:
  NoiseStage(std::size_t receivers, bool shared, std::uint64_t seed, float unit_variance,
             std::size_t tick_samples);

  void advance(SampleTime tick_start, bool applies) override;
  void apply(std::size_t node, SampleTime first_sample, std::span<cf32> x) const override;

 private:
  std::vector<NoiseSource> own_;  // per receiver, unless shared
  std::optional<NoiseSource> shared_;
  std::vector<cf32> shared_tick_;  // the shared stream's samples of this tick
  SampleTime tick_start_ = 0;
};

}  // namespace rfsitl::channel
