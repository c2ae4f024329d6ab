// The MAC "none": the paper's behaviour. A frame starts at the first tick at
// which its transmitter is idle, without listening first, and is sent once.
#include <memory>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/mac/mac.hpp"

namespace rfsitl::mac {
namespace {

struct NoneSettings {};

class NoneMac final : public Mac {
 public:
  explicit NoneMac(const MacContext& c) : max_payload_(c.radio_max_payload) {}

  std::size_t header_bytes() const override { return 0; }
  std::size_t max_radio_payload() const override { return max_payload_; }
  std::optional<double> carrier_sense_db() const override { return std::nullopt; }

  std::optional<MacTransmission> on_tick(SampleTime, bool tx_busy, FrameQueue& queue) override {
    if (tx_busy || queue.peek() == nullptr) return std::nullopt;
    frame_ = queue.take();
    return MacTransmission{frame_.kind, frame_.dst, &frame_, {}, false, false};
  }

  std::string describe() const override { return "none (send when the transmitter is idle)"; }

 private:
  std::size_t max_payload_;
  NetFrame frame_;  // the frame last taken, until the engine has copied it
};

}  // namespace

MacComponent none_component() {
  static const auto fields = config::Fields<NoneSettings>();
  return {fields.info("mac", "none",
                      "no medium access control: a frame starts at the first tick its "
                      "transmitter is idle, without carrier sense, and is sent once (the paper's "
                      "behaviour)"),
          [](const config::Settings&, const MacContext& c) -> std::unique_ptr<Mac> {
            return std::make_unique<NoneMac>(c);
          }};
}

}  // namespace rfsitl::mac
