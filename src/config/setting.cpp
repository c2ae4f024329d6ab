#include "rfsitl/config/setting.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>

namespace rfsitl::config {
namespace {

std::string number(double v) {
  std::array<char, 32> buf{};
  return {buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr};
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out.append(out.empty() ? "" : ", ").append(n);
  return out;
}

}  // namespace

std::string_view type_name(ValueType type) {
  switch (type) {
    case ValueType::kBool:
      return "true or false";
    case ValueType::kInteger:
      return "an integer";
    case ValueType::kReal:
      return "a number";
    case ValueType::kText:
      break;
  }
  return "a string";
}

ValueType type_of(const Value& v) {
  return static_cast<ValueType>(v.index());  // the enumerators follow the variant's order
}

std::string to_text(const Value& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (const auto* u = std::get_if<std::uint64_t>(&v)) return std::to_string(*u);
  if (const auto* d = std::get_if<double>(&v)) return number(*d);
  return std::get<std::string>(v);
}

bool Range::contains(double v) const {
  return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

std::string Setting::limits_text() const {
  if (!choices.empty()) return join(choices);
  if (!range) return "";
  const Range& r = *range;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (type == ValueType::kInteger) {
    return r.hi == kInf ? ">= " + number(r.lo) : number(r.lo) + ".." + number(r.hi);
  }
  if (r.lo == -kInf && r.hi == kInf) return "finite";
  if (r.hi == kInf) return (r.lo_open ? "> " : ">= ") + number(r.lo);
  return (r.lo_open ? "(" : "[") + number(r.lo) + ", " + number(r.hi) + (r.hi_open ? ")" : "]");
}

std::optional<std::string> Setting::reject_reason(const Value& v) const {
  if (type_of(v) != type) return "expected " + std::string(type_name(type)) + ", got " + to_text(v);
  if (!choices.empty()) {
    const std::string t = to_text(v);
    if (std::find(choices.begin(), choices.end(), t) == choices.end()) {
      return "unknown '" + t + "' (known: " + join(choices) + ")";
    }
  }
  if (!range) return std::nullopt;
  if (const auto* u = std::get_if<std::uint64_t>(&v)) {
    // Integer limits are whole numbers far below 2^53, so the comparison is exact.
    if (static_cast<double>(*u) < range->lo || static_cast<double>(*u) > range->hi) {
      return "must be in " + limits_text() + ", got " + std::to_string(*u);
    }
    return std::nullopt;
  }
  const double d = std::get<double>(v);
  if (range->contains(d)) return std::nullopt;
  const std::string lim = limits_text();
  const bool interval = lim.front() == '(' || lim.front() == '[';
  return (lim == "finite" ? "must be a finite number"
                          : (interval ? "must be in " : "must be ") + lim) +
         ", got " + number(d);
}

}  // namespace rfsitl::config
