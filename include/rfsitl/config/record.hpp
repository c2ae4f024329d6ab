#pragma once
/// List settings: a value that is a list of records, each record a few named
/// numbers (a waypoint {t, x, y, z}, a channel tap {delay_ns, gain_db}, an
/// occlusion sector). The owner declares the numeric fields an item may hold
/// (unit, limits, doc, whether required) and how many items there may be;
/// fields.hpp binds them to a struct (record_fields.hpp).
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rfsitl/config/range.hpp"

namespace rfsitl::config {

/// One item of a list setting as given: the fields present, in declaration
/// order (the readers keep it), each once.
class Record {
 public:
  Record() = default;
  Record(std::initializer_list<std::pair<std::string, double>> fields);

  /// The value of `name`, or nullptr when the item does not give it.
  const double* find(std::string_view name) const;
  /// Sets `name` (replacing, or appending in order).
  void set(std::string_view name, double value);

  auto begin() const { return fields_.begin(); }
  auto end() const { return fields_.end(); }
  std::size_t size() const { return fields_.size(); }
  bool operator==(const Record&) const = default;

 private:
  std::vector<std::pair<std::string, double>> fields_;
};

using Records = std::vector<Record>;

/// `[{t: 0, x: 1}, {t: 10, x: 100}]`, as a scenario file may write it; "[]" when empty.
std::string to_text(const Records& items);

/// Where inside a value a fault lies, and why: `where` is "" for the value as
/// a whole, "[2]" for an item, "[2].t" for one of its fields.
struct Rejection {
  std::string where;
  std::string reason;
};

/// The declaration of one numeric field of a list setting's items.
struct RecordField {
  std::string name;  ///< the key within an item, snake_case
  std::string unit;  ///< as Setting::unit
  Range range;       ///< every value given must lie in it
  std::string doc;   ///< one line, no trailing period
  /// What an item that leaves the field out means: this value, or (nullopt)
  /// "not given", which the owner's rules interpret (e.g. a waypoint gives
  /// either a time or a speed).
  std::optional<double> default_value;
  bool required = false;  ///< an item must give it (then default_value is unused)
};

/// What a list setting's items hold and how many of them there may be.
struct RecordShape {
  std::vector<RecordField> fields;
  std::size_t min_items = 0;
  std::size_t max_items = std::numeric_limits<std::size_t>::max();

  /// The declaration of `name`, or nullptr.
  const RecordField* find(std::string_view name) const;

  /// The field names, comma-separated (for "unknown key" messages).
  std::string field_names() const;

  /// "1..1000 items", ">= 1 items", "" when any number goes.
  std::string count_text() const;

  /// Why `items` is not acceptable: the count ("must hold at least 1 item,
  /// got 0"), or the first item with a field it may not give, lacks a required
  /// one, or gives one outside its range ({"[1].t", "must be >= 0, got -3"}).
  /// nullopt when every item is acceptable.
  std::optional<Rejection> rejection(const Records& items) const;
};

}  // namespace rfsitl::config
