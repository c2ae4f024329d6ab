#include "rfsitl/config/settings.hpp"

#include <algorithm>

namespace rfsitl::config {

const Value* Settings::find(std::string_view name) const {
  const auto it = std::find_if(values_.begin(), values_.end(),
                               [name](const auto& kv) { return kv.first == name; });
  return it == values_.end() ? nullptr : &it->second;
}

void Settings::set(std::string_view name, Value value) {
  const auto it = std::find_if(values_.begin(), values_.end(),
                               [name](const auto& kv) { return kv.first == name; });
  if (it != values_.end()) {
    it->second = std::move(value);
  } else {
    values_.emplace_back(std::string(name), std::move(value));
  }
}

void Settings::missing(std::string_view name) {
  throw std::logic_error("setting '" + std::string(name) + "' is not set or has another type");
}

}  // namespace rfsitl::config
