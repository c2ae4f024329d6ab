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

#include "rfsitl/config/range.hpp"
#include "rfsitl/config/record.hpp"

namespace rfsitl::config {

/// A setting's value. Integers are unsigned (no setting needs a sign). A list
/// setting holds records (record.hpp).
using Value = std::variant<bool, std::uint64_t, double, std::string, Records>;

/// In the order of Value's alternatives.
enum class ValueType { kBool, kInteger, kReal, kText, kRecords };

/// "true or false", "an integer", "a number", "a string", "a list".
std::string_view type_name(ValueType type);

/// The type a value holds.
ValueType type_of(const Value& v);

/// The value as a scenario file would write it: true, 12, 0.5, barker11,
/// [{t: 0, x: 1}].
std::string to_text(const Value& v);

struct Setting {
  std::string name;  ///< the key in a scenario file, snake_case
  ValueType type = ValueType::kText;
  Value default_value;
  std::string unit;                  ///< SI or "bytes", "samples", ...; "" if none
  std::string doc;                   ///< one line, no trailing period
  std::optional<Range> range;        ///< integers and reals
  std::vector<std::string> choices;  ///< when only these values are allowed (as text)
  RecordShape items;                 ///< kRecords: what an item holds, how many there may be

  /// Why `v` is not acceptable ({"", "must be in 2..8, got 12"}; for a list,
  /// possibly {"[1].t", "must be >= 0, got -3"}), or nullopt when it is.
  std::optional<Rejection> rejection(const Value& v) const;

  /// The limits in words: "2..8", "(0, 1]", "> 0", "6, 9, 12", "1..100 items";
  /// "" when any value goes.
  std::string limits_text() const;
};

}  // namespace rfsitl::config
