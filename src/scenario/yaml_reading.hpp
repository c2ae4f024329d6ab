#pragma once
// Internal to the scenario module: reading YAML into settings with errors that
// point at "<source>:<line>: <dotted.key>". Scalars are checked for their type
// (a quoted "5" is a string, not a number), mappings for unknown and duplicate
// keys, lists item by item, and a component's declared settings against its
// declaration. Shared by the scenario reader (scenario_loader.cpp) and the
// channel's reader (channel_reading.cpp).
#include <yaml-cpp/yaml.h>

#include <concepts>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/config/component_info.hpp"
#include "rfsitl/config/setting.hpp"
#include "scenario_rules.hpp"

namespace rfsitl::scenario::detail {

int line_of(const YAML::Node& n);

/// "'text'", "a list", "a mapping" or "nothing": what was found instead.
std::string kind_of(const YAML::Node& n);

/// The value under a dotted key; undefined when the key is absent.
struct Entry {
  YAML::Node value;
  std::string key;
  explicit operator bool() const { return value.IsDefined(); }
};

std::string text(const Context& c, const Entry& e);
bool boolean(const Context& c, const Entry& e);
/// Any finite number; validate() applies the setting's own range.
double real(const Context& c, const Entry& e);
/// 1000, +1000 and 1e3 are the same integer; 1.5 is not an integer.
std::uint64_t integer(const Context& c, const Entry& e, IntLimit lim);

/// One mapping being read. Every key the code asks for is known; finish() turns
/// any other key into an error, so that a typo such as `tick_sample` is never
/// silently ignored.
class Section {
 public:
  Section(Context& c, const Entry& at);

  /// The value under `leaf`; undefined when absent.
  Entry take(std::string_view leaf);
  Entry require(std::string_view leaf);

  template <std::unsigned_integral T>
  void get(std::string_view leaf, T& out, IntLimit lim) {
    if (const Entry e = take(leaf)) out = static_cast<T>(integer(c_, e, lim));
  }
  template <std::floating_point T>
  void get(std::string_view leaf, T& out) {
    if (const Entry e = take(leaf)) out = static_cast<T>(real(c_, e));
  }
  void get(std::string_view leaf, bool& out) {
    if (const Entry e = take(leaf)) out = boolean(c_, e);
  }
  void get(std::string_view leaf, std::string& out) {
    if (const Entry e = take(leaf)) out = text(c_, e);
  }

  /// Keys present but never asked for (so far).
  std::vector<std::string> unknown_keys() const;

  void finish() const;

 private:
  std::string child(std::string_view leaf) const;

  Context& c_;
  Entry at_;
  YAML::Node map_{YAML::NodeType::Map};
  std::vector<std::string_view> known_;
};

/// Calls read(item) for every entry of a list; absent or empty means no entries.
template <typename Read>
void for_each_item(Context& c, const Entry& list, Read read) {
  if (!list || list.value.IsNull()) return;
  if (!list.value.IsSequence()) c.fail(list.key, "expected a list, got " + kind_of(list.value));
  std::size_t i = 0;
  for (const auto& item : list.value) {
    const Entry e{item, list.key + "[" + std::to_string(i++) + "]"};
    c.record(e.key, line_of(item));
    read(e);
  }
}

/// {lat, lon, alt}, {x, y, z} or "lat lon alt" (as on the location feed). No
/// position (absent or empty) means the node is placed by its location feed.
/// Ranges: validate().
std::optional<Position> read_position(Context& c, const Entry& e);

/// The settings `info` declares, read from `sec` into `settings` (which holds
/// their values so far), then checked with the component's own rules. `others`
/// (components of the same kind) name the owner of a key this one lacks.
void read_declared(Context& c, Section& sec, const Entry& at, const config::ComponentInfo& info,
                   const std::vector<const config::ComponentInfo*>& others,
                   config::Settings& settings);

}  // namespace rfsitl::scenario::detail
