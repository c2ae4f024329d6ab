#pragma once
/// Symbol-by-symbol coherent detection of GMSK's Laurent pseudo-symbols, with a
/// decision-directed second-order phase-locked loop.
///
/// Symbol s's matched-filter sample is r_s ~ G j^s c_s (see frame_format.hpp), so
/// z_s = r_s j^-s / G ~ c_s: the bit is the sign of Re z_s (the real axis of
/// every symbol, which makes this an MSK-type I/Q detector with one matched
/// filter). Im z_s d_s (d_s the decision) is the phase error, which turns the
/// equaliser 1/G by a proportional and an integral (frequency) term, so a slow
/// drift or a small carrier offset is followed through long frames. The loop
/// gains are low: the quadrature interference of the neighbouring symbols also
/// lands in Im z and must average out.
#include <cstddef>
#include <cstdint>
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class CoherentDetector {
 public:
  /// Starts a frame: `gain` is G at the next symbol, `first_index` that
  /// symbol's index s counted from the first sync symbol (only s mod 4
  /// matters) and `frequency` the carrier offset in radians per symbol.
  void start(cf32 gain, std::size_t first_index, float frequency);

  /// Decides the next mf.size() symbols from their matched-filter samples:
  /// writes each bit (0 for pseudo-symbol +1, 1 for -1) to bits[i] and z_s to
  /// soft[i]. The loop is one long dependency chain (each symbol's decision
  /// turns the equaliser of the next), so it is a loop over a block with the
  /// state in registers rather than a call per symbol.
  void decide(std::span<const cf32> mf, cf32* soft, std::uint8_t* bits);

 private:
  static constexpr float kPhaseGain = 0.02F;
  static constexpr float kFrequencyGain = 2e-4F;

  float eq_re_ = 1.0F;  // the equaliser 1 / G, turned by the loop
  float eq_im_ = 0.0F;
  float magnitude2_ = 1.0F;  // |1 / G|^2, kept while the loop turns the phase
  float frequency_ = 0.0F;   // radians per symbol
  unsigned quarter_ = 0;     // s mod 4
  unsigned since_renormalised_ = 0;
};

}  // namespace rfsitl::phy::gmsk
