#include "rfsitl/phy/gfsk/gfsk_modulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rfsitl/phy/gmsk/gmsk_pulse.hpp"

namespace rfsitl::phy::gfsk {

unsigned gaussian_span_symbols(float bt) {
  if (bt <= 0.0F) return 1;
  const double sigma = std::sqrt(std::numbers::ln2) / (2.0 * std::numbers::pi * bt);
  return static_cast<unsigned>(std::ceil(1.0 + 6.0 * sigma));
}

GfskModulator::GfskModulator(unsigned k, float h, float bt)
    : k_(k), span_(gaussian_span_symbols(bt)), h_(h), ramp_(span_ * k + 1) {
  if (bt > 0.0F) {
    // The GMSK table holds pi q(j / k) (h = 1/2); scale it to 2 pi h q.
    const gmsk::GmskPulse pulse = gmsk::make_gmsk_pulse(k, bt, span_);
    for (std::size_t j = 0; j < ramp_.size(); ++j) ramp_[j] = 2.0 * h_ * pulse.phase[j];
  } else {
    for (std::size_t j = 0; j <= k; ++j)
      ramp_[j] = std::numbers::pi * h_ * static_cast<double>(j) / static_cast<double>(k);
  }
}

std::size_t GfskModulator::start(std::span<const std::int8_t> symbols) {
  symbols_ = symbols;
  total_ = frame_samples(symbols.size());
  pos_ = 0;
  finished_ = 0;
  return total_;
}

std::size_t GfskModulator::generate(std::span<cf32> out) {
  const std::size_t n = std::min(out.size(), samples_left());
  const std::size_t count = symbols_.size();
  for (std::size_t s = 0; s < n; ++s, ++pos_) {
    const std::size_t sym = pos_ / k_;
    const std::size_t j = pos_ % k_;
    // Symbol sym - L finishes its pulse at this symbol boundary.
    if (j == 0 && sym >= span_ && sym - span_ < count) finished_ += symbols_[sym - span_];
    // The finished symbols' phase, pi h times their sum, reduced modulo 2 pi.
    double phase = std::numbers::pi * std::fmod(h_ * static_cast<double>(finished_), 2.0);
    const std::size_t first = sym + 1 >= span_ ? sym + 1 - span_ : 0;
    const std::size_t last = std::min(sym, count - 1);
    for (std::size_t i = first; i <= last; ++i) {
      phase += symbols_[i] * ramp_[(sym - i) * k_ + j];
    }
    out[s] = std::polar(1.0F, static_cast<float>(phase));
  }
  return n;
}

}  // namespace rfsitl::phy::gfsk
