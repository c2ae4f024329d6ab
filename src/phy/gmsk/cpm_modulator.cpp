#include "cpm_modulator.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace rfsitl::phy::gmsk {

CpmPulse gaussian_cpm_pulse(const GmskPulse& pulse, double h) {
  CpmPulse p;
  p.samples_per_symbol = pulse.samples_per_symbol;
  p.span_symbols = pulse.span_symbols;
  p.modulation_index = h;
  p.phase.resize(pulse.phase.size());
  // Written as (2 h) times the table: at h = 1/2 that is 1.0 times it, exact.
  for (std::size_t j = 0; j < p.phase.size(); ++j) p.phase[j] = 2.0 * h * pulse.phase[j];
  return p;
}

CpmPulse rectangular_cpm_pulse(unsigned k, double h) {
  CpmPulse p;
  p.samples_per_symbol = k;
  p.span_symbols = 1;
  p.modulation_index = h;
  p.phase.resize(k + 1);
  for (std::size_t j = 0; j <= k; ++j) {
    p.phase[j] = std::numbers::pi * h * static_cast<double>(j) / static_cast<double>(k);
  }
  return p;
}

CpmModulator::CpmModulator(CpmPulse pulse, CpmArithmetic arithmetic)
    : k_(pulse.samples_per_symbol),
      span_(pulse.span_symbols),
      h_(pulse.modulation_index),
      arithmetic_(arithmetic),
      phase_(std::move(pulse.phase)) {
  if (arithmetic_ == CpmArithmetic::kFloatQuarterTurns) {
    if (h_ != 0.5) {
      throw std::invalid_argument("CpmModulator: quarter turns need h = 1/2, got " +
                                  std::to_string(h_));
    }
    phase_float_.assign(phase_.begin(), phase_.end());
  }
}

std::size_t CpmModulator::start(std::span<const std::int8_t> symbols) {
  symbols_ = symbols;
  total_ = frame_samples(symbols.size());
  pos_ = 0;
  finished_ = 0;
  return total_;
}

std::size_t CpmModulator::generate(std::span<cf32> out) {
  return arithmetic_ == CpmArithmetic::kFloatQuarterTurns
             ? generate_as<CpmArithmetic::kFloatQuarterTurns>(out)
             : generate_as<CpmArithmetic::kDouble>(out);
}

std::size_t CpmModulator::transmit(std::span<cf32> out) {
  const std::size_t n = generate(out);
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
  return n;
}

// The arithmetic of each mode is spelled out term by term, in the order the
// two modulators this one replaced used, so that their samples stay the same
// to the bit (the unit tests compare against a double-precision reference).
template <CpmArithmetic kArithmetic>
std::size_t CpmModulator::generate_as(std::span<cf32> out) {
  const std::size_t n = std::min(out.size(), samples_left());
  const std::size_t count = symbols_.size();
  for (std::size_t w = 0; w < n; ++w, ++pos_) {
    const std::size_t s = pos_ / k_;
    const std::size_t r = pos_ % k_;
    // At the start of symbol s, symbol s - L has completed its pulse: its +-pi h
    // moves from the active sum to the finished one.
    if (r == 0 && s >= span_ && s - span_ < count) finished_ += symbols_[s - span_];
    const std::size_t first = s + 1 >= span_ ? s + 1 - span_ : 0;
    const std::size_t end = std::min(s + 1, count);
    if constexpr (kArithmetic == CpmArithmetic::kFloatQuarterTurns) {
      float active = 0.0F;
      for (std::size_t i = first; i < end; ++i) {
        active += static_cast<float>(symbols_[i]) * phase_float_[(s - i) * k_ + r];
      }
      const cf32 v = std::polar(1.0F, active);
      // Times j^(finished mod 4), exactly (two's complement: -1 & 3 == 3).
      switch (finished_ & 3) {
        case 0:
          out[w] = v;
          break;
        case 1:
          out[w] = cf32{-v.imag(), v.real()};
          break;
        case 2:
          out[w] = -v;
          break;
        default:
          out[w] = cf32{v.imag(), -v.real()};
          break;
      }
    } else {
      // The finished symbols' phase, pi h times their sum, reduced modulo 2 pi.
      double phase = std::numbers::pi * std::fmod(h_ * static_cast<double>(finished_), 2.0);
      for (std::size_t i = first; i < end; ++i) {
        phase += static_cast<double>(symbols_[i]) * phase_[(s - i) * k_ + r];
      }
      out[w] = std::polar(1.0F, static_cast<float>(phase));
    }
  }
  return n;
}

}  // namespace rfsitl::phy::gmsk
