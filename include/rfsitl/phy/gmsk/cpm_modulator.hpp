#pragma once
/// Streaming GMSK modulator: exact sampled CPM phase, unit amplitude.
///
/// Sample n of a frame of N symbols a_0..a_{N-1} (each +1 or -1) is
///   x[n] = exp(j pi sum_i a_i qt((n - i k) / k)),
/// qt being the truncated phase pulse of GmskPulse (symbol i's pulse starts at
/// sample i k). Symbols whose pulse has ended contribute exactly +-pi/2 each, so
/// they are kept as a quarter-turn count modulo 4 (no rounding accumulates
/// however long the frame); only the at most L symbols still inside their pulse
/// are summed per sample. The frame lasts (N + L - 1) k samples, after which the
/// last symbol's pulse is complete.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/phy/gmsk/gmsk_pulse.hpp"

namespace rfsitl::phy::gmsk {

class CpmModulator {
 public:
  explicit CpmModulator(const GmskPulse& pulse);

  /// Samples a frame of `symbols` symbols occupies.
  std::size_t frame_samples(std::size_t symbols) const {
    return symbols == 0 ? 0 : (symbols + span_ - 1) * k_;
  }

  /// Starts a frame. `symbols` (each +1 or -1) must stay alive and unchanged
  /// until the frame has been generated. Returns frame_samples(symbols.size()).
  std::size_t start(std::span<const std::int8_t> symbols);

  /// Samples of the current frame not generated yet.
  std::size_t samples_left() const { return total_ - pos_; }

  /// Writes min(out.size(), samples_left()) samples to the front of `out` and
  /// returns that count; the rest of `out` is left untouched.
  std::size_t generate(std::span<cf32> out);

 private:
  unsigned k_;
  unsigned span_;
  std::vector<float> phase_;  // pi qt(j / k), j = 0 .. L k
  std::span<const std::int8_t> symbols_;
  std::size_t total_ = 0;
  std::size_t pos_ = 0;
  unsigned quarter_turns_ = 0;  // sum of the finished symbols, modulo 4
};

}  // namespace rfsitl::phy::gmsk
