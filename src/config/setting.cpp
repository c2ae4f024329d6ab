#include "rfsitl/config/setting.hpp"

#include <algorithm>
#include <limits>

namespace rfsitl::config {
namespace {

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
      return "a string";
    case ValueType::kRecords:
      break;
  }
  return "a list";
}

ValueType type_of(const Value& v) {
  return static_cast<ValueType>(v.index());  // the enumerators follow the variant's order
}

std::string to_text(const Value& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (const auto* u = std::get_if<std::uint64_t>(&v)) return std::to_string(*u);
  if (const auto* d = std::get_if<double>(&v)) return number_text(*d);
  if (const auto* r = std::get_if<Records>(&v)) return to_text(*r);
  return std::get<std::string>(v);
}

std::string Setting::limits_text() const {
  if (type == ValueType::kRecords) return items.count_text();
  if (!choices.empty()) return join(choices);
  if (!range) return "";
  const Range& r = *range;
  if (type == ValueType::kInteger) {
    return r.hi == std::numeric_limits<double>::infinity()
               ? ">= " + number_text(r.lo)
               : number_text(r.lo) + ".." + number_text(r.hi);
  }
  return r.text();
}

std::optional<Rejection> Setting::rejection(const Value& v) const {
  if (type_of(v) != type) {
    return Rejection{"", "expected " + std::string(type_name(type)) + ", got " + to_text(v)};
  }
  if (const auto* r = std::get_if<Records>(&v)) return items.rejection(*r);
  if (!choices.empty()) {
    const std::string t = to_text(v);
    if (std::find(choices.begin(), choices.end(), t) == choices.end()) {
      return Rejection{"", "unknown '" + t + "' (known: " + join(choices) + ")"};
    }
  }
  if (!range) return std::nullopt;
  if (const auto* u = std::get_if<std::uint64_t>(&v)) {
    // Integer limits are whole numbers far below 2^53, so the comparison is exact.
    if (static_cast<double>(*u) < range->lo || static_cast<double>(*u) > range->hi) {
      return Rejection{"", "must be in " + limits_text() + ", got " + std::to_string(*u)};
    }
    return std::nullopt;
  }
  if (auto why = range->reject_reason(std::get<double>(v))) return Rejection{"", *why};
  return std::nullopt;
}

}  // namespace rfsitl::config
