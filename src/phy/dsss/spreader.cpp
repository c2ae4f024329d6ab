#include "spreader.hpp"

#include <algorithm>

namespace rfsitl::phy::dsss {

void Spreader::start(std::span<const Chip> chips, unsigned samples_per_chip,
                     std::vector<cf32> symbols) {
  chips_.assign(chips.begin(), chips.end());
  symbols_ = std::move(symbols);
  samples_per_chip_ = samples_per_chip;
  total_ = symbols_.size() * chips_.size() * samples_per_chip_;
  position_ = 0;
}

std::size_t Spreader::write(std::span<cf32> out) {
  const std::size_t n = std::min(out.size(), remaining());
  const std::size_t period = chips_.size() * samples_per_chip_;
  std::size_t written = 0;
  while (written < n) {
    const std::size_t symbol = position_ / period;
    const std::size_t in_period = position_ % period;
    const std::size_t chip = in_period / samples_per_chip_;
    const std::size_t run =
        std::min(n - written, samples_per_chip_ - in_period % samples_per_chip_);
    const cf32 value = symbols_[symbol] * static_cast<float>(chips_[chip]);
    std::fill_n(out.begin() + static_cast<std::ptrdiff_t>(written), run, value);
    written += run;
    position_ += run;
  }
  return n;
}

std::vector<cf32> spread(std::span<const cf32> symbols, std::span<const Chip> chips,
                         unsigned samples_per_chip) {
  Spreader s;
  s.start(chips, samples_per_chip, {symbols.begin(), symbols.end()});
  std::vector<cf32> out(s.remaining());
  s.write(out);
  return out;
}

}  // namespace rfsitl::phy::dsss
