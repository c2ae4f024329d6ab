#include "rfsitl/phy/gmsk/cpm_modulator.hpp"

#include <complex>

namespace rfsitl::phy::gmsk {

CpmModulator::CpmModulator(const GmskPulse& pulse)
    : k_(pulse.samples_per_symbol),
      span_(pulse.span_symbols),
      phase_(pulse.phase.begin(), pulse.phase.end()) {}

std::size_t CpmModulator::start(std::span<const std::int8_t> symbols) {
  symbols_ = symbols;
  total_ = frame_samples(symbols.size());
  pos_ = 0;
  quarter_turns_ = 0;
  return total_;
}

std::size_t CpmModulator::generate(std::span<cf32> out) {
  std::size_t written = 0;
  const std::size_t n_symbols = symbols_.size();
  while (written < out.size() && pos_ < total_) {
    const std::size_t s = pos_ / k_;
    const std::size_t r = pos_ % k_;
    // At the start of symbol s, symbol s - L has turned the phase by its full
    // +-pi/2 and leaves the sum of active pulses for the quarter-turn count.
    if (r == 0 && s >= span_ && s - span_ < n_symbols) {
      quarter_turns_ = (quarter_turns_ + (symbols_[s - span_] > 0 ? 1U : 3U)) & 3U;
    }
    float active = 0.0F;
    const std::size_t first = s + 1 >= span_ ? s + 1 - span_ : 0;
    for (std::size_t i = first; i <= s && i < n_symbols; ++i) {
      active += static_cast<float>(symbols_[i]) * phase_[(s - i) * k_ + r];
    }
    const cf32 v = std::polar(1.0F, active);
    // Multiply by j^quarter_turns_ exactly.
    switch (quarter_turns_) {
      case 0:
        out[written] = v;
        break;
      case 1:
        out[written] = cf32{-v.imag(), v.real()};
        break;
      case 2:
        out[written] = -v;
        break;
      default:
        out[written] = cf32{v.imag(), -v.real()};
        break;
    }
    ++written;
    ++pos_;
  }
  return written;
}

}  // namespace rfsitl::phy::gmsk
