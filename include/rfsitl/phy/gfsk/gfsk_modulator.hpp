#pragma once
/// Streaming continuous-phase 2-FSK modulator with an optional Gaussian
/// frequency pulse; unit amplitude.
///
/// Sample n of a frame of symbols a_0..a_{N-1} (each +1 or -1) is
///   x[n] = exp(j 2 pi h sum_i a_i q((n - i k) / k)),
/// q being the phase pulse, rising from 0 to 1/2 over L symbols: for BT > 0
/// the GMSK pulse of rfsitl/phy/gmsk/gmsk_pulse.hpp (a Gaussian-filtered
/// rectangle, truncated to L = ceil(1 + 6 sigma) symbols, sigma = sqrt(ln 2) /
/// (2 pi BT) the Gaussian's width in symbols: 3 symbols at BT = 0.5, 5 at 0.2);
/// for BT = 0 a linear ramp over one symbol (plain CPFSK). Each finished
/// symbol has turned the phase by +-pi h; they are kept as an integer sum, so
/// nothing accumulates however long the frame. The instantaneous frequency of
/// a long run of equal symbols is +-fd = +-h / (2 k) cycles per sample. A
/// frame lasts (N + L - 1) k samples.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gfsk {

/// L for a BT (1 for BT = 0).
unsigned gaussian_span_symbols(float bandwidth_time);

class GfskModulator {
 public:
  /// Preconditions: k >= 1, h > 0, BT == 0 or BT > 0.
  GfskModulator(unsigned samples_per_symbol, float modulation_index, float bandwidth_time);

  unsigned span_symbols() const { return span_; }

  /// Samples a frame of `symbols` symbols occupies.
  std::size_t frame_samples(std::size_t symbols) const {
    return symbols == 0 ? 0 : (symbols + span_ - 1) * k_;
  }

  /// Starts a frame; `symbols` must stay alive and unchanged until it has been
  /// generated. Returns frame_samples(symbols.size()).
  std::size_t start(std::span<const std::int8_t> symbols);

  std::size_t samples_left() const { return total_ - pos_; }

  /// Writes min(out.size(), samples_left()) samples to the front of `out` and
  /// returns that count; the rest of `out` is left untouched.
  std::size_t generate(std::span<cf32> out);

 private:
  unsigned k_;
  unsigned span_;
  double h_;
  std::vector<double> ramp_;  // 2 pi h q(j / k), j = 0 .. L k
  std::span<const std::int8_t> symbols_;
  std::size_t total_ = 0;
  std::size_t pos_ = 0;
  std::int64_t finished_ = 0;  // sum of the symbols whose pulse has ended
};

}  // namespace rfsitl::phy::gfsk
