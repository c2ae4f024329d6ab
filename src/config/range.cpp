#include "rfsitl/config/range.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>

namespace rfsitl::config {

std::string number_text(double v) {
  std::array<char, 32> buf{};
  return {buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr};
}

bool Range::contains(double v) const {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string Range::text() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (lo == -kInf && hi == kInf) return "finite";
  if (hi == kInf) return (lo_open ? "> " : ">= ") + number_text(lo);
  return (lo_open ? "(" : "[") + number_text(lo) + ", " + number_text(hi) + (hi_open ? ")" : "]");
}

std::optional<std::string> Range::reject_reason(double v) const {
  if (contains(v)) return std::nullopt;
  const std::string lim = text();
  const bool interval = lim.front() == '(' || lim.front() == '[';
  return (lim == "finite" ? "must be a finite number"
                          : (interval ? "must be in " : "must be ") + lim) +
         ", got " + number_text(v);
}

}  // namespace rfsitl::config
