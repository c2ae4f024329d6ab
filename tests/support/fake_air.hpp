#pragma once
/// The medium that FakeTransceivers share (a test double, no DSP). Every frame
/// a fake puts on the air is registered here with its virtual start time and
/// contents, so that a fake receiver can recognise the frame's waveform in the
/// samples it actually receives (what the channel made of it) and look up what
/// it carries instead of demodulating it.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::testing {

/// One frame on the air. Immutable once registered.
struct AirFrame {
  std::uint64_t id = 0;          ///< unique per FakeAir (assigned by add); seeds the waveform
  const void* sender = nullptr;  ///< the transceiver that sent it; its own receiver ignores it
  phy::FrameTag tag;             ///< what the receiver reports on a decode
  std::vector<std::uint8_t> payload;
  SampleTime start = 0;            ///< virtual time of its first sample
  std::size_t header_samples = 0;  ///< leading samples that stand for the header
  std::size_t length = 0;          ///< samples on the air, header included

  SampleTime end() const { return start + static_cast<SampleTime>(length); }

  /// Sample j (0 <= j < length) of the waveform, at unit power: a pseudo-random
  /// QPSK point drawn from (id, j), so that two frames' waveforms are
  /// uncorrelated and a receiver can measure each frame's power apart from
  /// everything else it hears.
  cf32 sample(std::size_t j) const;
};

/// Thread-safe: the engine's TX workers register frames while (in a later
/// phase) its RX workers look them up.
class FakeAir {
 public:
  /// Frames that ended more than `retention_samples` before the newest one
  /// started are forgotten (a receiver that still tracks one keeps its copy).
  explicit FakeAir(SampleTime retention_samples = SampleTime{1} << 22);

  /// Registers a frame (its id is assigned here) and returns the shared copy.
  std::shared_ptr<const AirFrame> add(AirFrame frame);

  /// Frames not sent by `receiver` whose first sample lies in [from, to), in
  /// registration order.
  std::vector<std::shared_ptr<const AirFrame>> starting_in(SampleTime from, SampleTime to,
                                                           const void* receiver) const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const AirFrame>> frames_;  // registration order
  std::uint64_t next_id_ = 1;
  SampleTime retention_;
};

}  // namespace rfsitl::testing
