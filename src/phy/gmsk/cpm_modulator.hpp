#pragma once
/// Streaming binary CPM (continuous-phase modulation) modulator, unit amplitude:
/// the transmitter of the GMSK and of the GFSK transceiver.
///
/// Sample n of a frame of N symbols a_0..a_{N-1} (each +1 or -1) is
///   x[n] = exp(j 2 pi h sum_i a_i q((n - i k) / k)),
/// q being the phase pulse (the integral of the frequency pulse), rising from 0
/// to 1/2 over L symbols, and symbol i's pulse starting at sample i k. A symbol
/// whose pulse has ended has turned the phase by exactly +-pi h, so those are
/// kept as an integer sum (no rounding accumulates however long the frame); only
/// the at most L symbols still inside their pulse are summed per sample. A frame
/// lasts (N + L - 1) k samples, after which the last symbol's pulse is complete.
/// The instantaneous frequency of a long run of equal symbols is +-h / (2 k)
/// cycles per sample.
///
/// Not thread-safe: one transmitter's object, used by one thread at a time.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "gmsk_pulse.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

/// A sampled phase pulse: the phase one +1 symbol turns the carrier by.
struct CpmPulse {
  unsigned samples_per_symbol = 0;  ///< k >= 1
  unsigned span_symbols = 0;        ///< L >= 1: length of the frequency pulse, symbols
  double modulation_index = 0.0;    ///< h > 0
  /// phase[j] = 2 pi h q(j / k) radians for j = 0 .. L k: front() == 0 and
  /// back() == pi h (to rounding).
  std::vector<double> phase;
};

/// The Gaussian pulse `pulse` (GMSK's, whose table is pi q) at index h: its
/// table times 2 h (so h = 1/2 leaves it unchanged, to the bit).
CpmPulse gaussian_cpm_pulse(const GmskPulse& pulse, double modulation_index);

/// The rectangular frequency pulse of one symbol (plain CPFSK, BT = 0): a
/// linear phase ramp from 0 to pi h. Preconditions: k >= 1, h > 0.
CpmPulse rectangular_cpm_pulse(unsigned samples_per_symbol, double modulation_index);

/// How the phase is computed. Both follow the definition above to within float
/// rounding (a few 1e-7 rad); both are kept, each for its transceiver, because
/// what a noisy receiver decodes, and so every scenario's counters, depends on
/// the exact bits of the samples.
enum class CpmArithmetic {
  /// The pulse table and the sum of the active pulses in float; the finished
  /// symbols as a count of quarter turns, applied after the exponential as an
  /// exact multiplication by j^count. Only for h = 1/2 (GMSK), where every
  /// finished symbol is a quarter turn.
  kFloatQuarterTurns,
  /// In double: pi fmod(h S, 2) for the finished symbols' sum S, plus the active
  /// pulses, rounded to float for the exponential. Any h (GFSK).
  kDouble,
};

class CpmModulator {
 public:
  /// Preconditions: `pulse` as documented at CpmPulse; kFloatQuarterTurns only
  /// with h == 0.5 (throws std::invalid_argument otherwise).
  CpmModulator(CpmPulse pulse, CpmArithmetic arithmetic);

  /// L: a symbol's pulse lasts this many symbols.
  unsigned span_symbols() const { return span_; }

  /// Samples a frame of `symbols` symbols occupies: (symbols + L - 1) k, 0 for none.
  std::size_t frame_samples(std::size_t symbols) const {
    return symbols == 0 ? 0 : (symbols + span_ - 1) * k_;
  }

  /// Starts a frame, abandoning any unfinished one. `symbols` (each +1 or -1)
  /// must stay alive and unchanged until the frame has been generated. Returns
  /// frame_samples(symbols.size()).
  std::size_t start(std::span<const std::int8_t> symbols);

  /// Samples of the current frame not generated yet.
  std::size_t samples_left() const { return total_ - pos_; }

  /// Writes min(out.size(), samples_left()) samples to the front of `out` and
  /// returns that count; the rest of `out` is left untouched.
  std::size_t generate(std::span<cf32> out);

  /// Transceiver::transmit's contract: generate(out), then zeros in the rest
  /// of `out` (the transmitter is silent after its frame). Returns the count
  /// generate() wrote.
  std::size_t transmit(std::span<cf32> out);

 private:
  template <CpmArithmetic kArithmetic>
  std::size_t generate_as(std::span<cf32> out);

  unsigned k_;
  unsigned span_;
  double h_;
  CpmArithmetic arithmetic_;
  std::vector<double> phase_;       // CpmPulse::phase (kDouble)
  std::vector<float> phase_float_;  // the same rounded to float (kFloatQuarterTurns)
  std::span<const std::int8_t> symbols_;
  std::size_t total_ = 0;
  std::size_t pos_ = 0;
  std::int64_t finished_ = 0;  // sum of the symbols whose pulse has ended
};

}  // namespace rfsitl::phy::gmsk
