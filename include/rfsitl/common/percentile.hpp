#pragma once
/// Percentiles as the reports print them (linear interpolation between ranks,
/// numpy's default). Header-only.
#include <algorithm>
#include <cmath>
#include <vector>

namespace rfsitl {

/// Percentile q in [0, 1] of ascending `sorted`; NaN when empty.
inline double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return NAN;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace rfsitl
