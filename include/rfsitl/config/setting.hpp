#pragma once
/// The declaration of one setting of a component (a PHY, a MAC, a channel stage,
/// a position source): its name, type, unit, default, limits and a one-line doc.
/// Declared once, by the component that owns it (see fields.hpp); the scenario
/// reader, the external protocol's JSON, `rfsitl describe` and the settings
/// tables in scenarios/README.md all work from this declaration.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rfsitl::config {

/// A setting's value. Integers are unsigned (no setting needs a sign).
using Value = std::variant<bool, std::uint64_t, double, std::string>;

enum class ValueType { kBool, kInteger, kReal, kText };

/// "true or false", "an integer", "a number", "a string".
std::string_view type_name(ValueType type);

/// The type a value holds.
ValueType type_of(const Value& v);

/// The value as a scenario file would write it: true, 12, 0.5, barker11.
std::string to_text(const Value& v);

/// An interval of a numeric setting. NaN and infinities are never inside.
struct Range {
  double lo = 0;
  double hi = 0;
  bool lo_open = false;
  bool hi_open = false;
  bool contains(double v) const;
};

struct Setting {
  std::string name;  ///< the key in a scenario file, snake_case
  ValueType type = ValueType::kText;
  Value default_value;
  std::string unit;                  ///< SI or "bytes", "samples", ...; "" if none
  std::string doc;                   ///< one line, no trailing period
  std::optional<Range> range;        ///< integers and reals
  std::vector<std::string> choices;  ///< when only these values are allowed (as text)

  /// Why `v` is not acceptable ("must be in 2..8, got 12"), or nullopt when it is.
  std::optional<std::string> reject_reason(const Value& v) const;

  /// The limits in words: "2..8", "(0, 1]", "> 0", "6, 9, 12"; "" when any value goes.
  std::string limits_text() const;
};

}  // namespace rfsitl::config
