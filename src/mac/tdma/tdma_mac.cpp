// The MAC "tdma": time is cut into frames of `slots` slots, and the k-th node
// of the scenario owns slot k mod slots. A node starts a frame only inside its
// own slot, and only if the frame ends `guard_us` before the slot does, so
// that a neighbour's slot starts on a quiet channel even with propagation
// delay. No carrier sense, no ACKs: the classic swarm MAC, collision-free as
// long as every node keeps to its slot. The largest frame a slot holds is the
// node's largest payload (an IP interface's MTU follows it).
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "../mac_timing.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/mac/mac.hpp"

namespace rfsitl::mac {
namespace {

struct TdmaSettings {
  double slot_ms = 40.0;  // holds a 2048-byte GMSK frame at 1 Msps (33 ms) and its guard
  double guard_us = 500.0;
  std::uint32_t slots = 0;  // 0: one per node
};

const config::Fields<TdmaSettings>& tdma_fields() {
  using S = TdmaSettings;
  static const auto f =
      config::Fields<S>()
          .real("slot_ms", &S::slot_ms, "ms", {0.001, 1e4},
                "length of one node's slot; rounded up to whole ticks")
          .real("guard_us", &S::guard_us, "us", {0.0, 1e7},
                "quiet time at the end of every slot: a frame must end this long before its "
                "slot does")
          .integer("slots", &S::slots, "", 0, 65535,
                   "slots per TDMA frame; node k (in the scenario's order) owns slot k mod "
                   "slots. 0: one slot per node");
  return f;
}

class TdmaMac final : public Mac {
 public:
  TdmaMac(const TdmaSettings& s, const MacContext& c)
      : c_(c),
        slots_(s.slots != 0 ? s.slots : c.num_nodes),
        slot_samples_(detail::ticks_of_us(s.slot_ms * 1e3, c) * c.tick_samples),
        guard_samples_(static_cast<std::size_t>(s.guard_us * 1e-6 * c.sample_rate_hz)),
        own_slot_(c.index % slots_) {
    const std::size_t usable = slot_samples_ > guard_samples_ ? slot_samples_ - guard_samples_ : 0;
    max_payload_ = detail::largest_payload_within(usable, c);
    if (max_payload_ == 0) {
      throw std::invalid_argument(
          "mac.slot_ms: a slot of " + std::to_string(slot_ms()) +
          " ms less the guard holds no frame of this PHY (an empty "
          "frame lasts " +
          std::to_string(static_cast<double>(c.frame_samples(0)) / c.sample_rate_hz * 1e3) +
          " ms)");
    }
  }

  std::size_t header_bytes() const override { return 0; }
  std::size_t max_radio_payload() const override { return max_payload_; }
  std::optional<double> carrier_sense_db() const override { return std::nullopt; }

  std::optional<MacTransmission> on_tick(SampleTime now, bool tx_busy, FrameQueue& queue) override {
    if (tx_busy) return std::nullopt;
    const NetFrame* next = queue.peek();
    if (next == nullptr) return std::nullopt;
    const auto slot = static_cast<SampleTime>(slot_samples_);
    const SampleTime in_frame = now % (slot * static_cast<SampleTime>(slots_));
    if (in_frame / slot != static_cast<SampleTime>(own_slot_)) return std::nullopt;
    const SampleTime left = slot - in_frame % slot - static_cast<SampleTime>(guard_samples_);
    // The engine refuses payloads over max_radio_payload(), so every frame fits
    // a whole slot; one that does not fit the rest of this one waits.
    if (static_cast<SampleTime>(c_.frame_samples(1 + next->payload.size())) > left) {
      return std::nullopt;
    }
    frame_ = queue.take();
    return MacTransmission{frame_.kind, frame_.dst, &frame_, {}, false, false};
  }

  std::string describe() const override {
    char line[200];
    std::snprintf(line, sizeof line,
                  "tdma: %zu slots of %.3f ms (guard %.0f us), this node's slot %zu; frames up "
                  "to %zu bytes",
                  slots_, slot_ms(), static_cast<double>(guard_samples_) / c_.sample_rate_hz * 1e6,
                  own_slot_, max_payload_);
    return line;
  }

 private:
  double slot_ms() const { return static_cast<double>(slot_samples_) / c_.sample_rate_hz * 1e3; }

  MacContext c_;
  std::size_t slots_;
  std::size_t slot_samples_;
  std::size_t guard_samples_;
  std::size_t own_slot_;
  std::size_t max_payload_ = 0;
  NetFrame frame_;  // the frame last taken, until the engine has copied it
};

}  // namespace

MacComponent tdma_component() {
  return {tdma_fields().info("mac", "tdma",
                             "fixed time slots, one per node in the scenario's order: a frame "
                             "starts only in its node's slot and ends a guard time before the "
                             "slot does; no carrier sense, no ACKs"),
          [](const config::Settings& settings, const MacContext& c) -> std::unique_ptr<Mac> {
            return std::make_unique<TdmaMac>(tdma_fields().build(settings), c);
          }};
}

}  // namespace rfsitl::mac
