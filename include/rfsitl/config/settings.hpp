#pragma once
/// The values of one component's settings, by name, in declaration order.
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rfsitl/config/setting.hpp"

namespace rfsitl::config {

/// A setting that cannot be used. key() is the setting's name within its
/// component ("samples_per_symbol"); the reader that knows where it came from
/// prefixes the path and the file's line.
class SettingError : public std::invalid_argument {
 public:
  SettingError(std::string key, const std::string& reason)
      : std::invalid_argument(reason), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

class Settings {
 public:
  /// The value of `name`, or nullptr when it is not set.
  const Value* find(std::string_view name) const;

  /// The value of `name` as T (bool, std::uint64_t, double, std::string or Records).
  /// Throws std::logic_error when it is absent or of another type: a component
  /// reads only settings it declared, and they are always present.
  template <typename T>
  const T& get(std::string_view name) const {
    const Value* v = find(name);
    if (v == nullptr || !std::holds_alternative<T>(*v)) missing(name);
    return std::get<T>(*v);
  }

  /// Sets `name` (replacing, or appending in order).
  void set(std::string_view name, Value value);

  auto begin() const { return values_.begin(); }
  auto end() const { return values_.end(); }
  std::size_t size() const { return values_.size(); }
  bool operator==(const Settings&) const = default;

 private:
  [[noreturn]] static void missing(std::string_view name);

  std::vector<std::pair<std::string, Value>> values_;
};

}  // namespace rfsitl::config
