#include "rfsitl/config/component_info.hpp"

#include <algorithm>

namespace rfsitl::config {

const Setting* ComponentInfo::find(std::string_view setting) const {
  const auto it = std::find_if(settings.begin(), settings.end(),
                               [setting](const Setting& s) { return s.name == setting; });
  return it == settings.end() ? nullptr : &*it;
}

Settings ComponentInfo::defaults() const {
  Settings s;
  for (const Setting& d : settings) s.set(d.name, d.default_value);
  return s;
}

void ComponentInfo::validate(const Settings& s) const {
  for (const auto& [key, value] : s) {
    if (find(key) == nullptr) throw SettingError(key, "not a setting of " + kind + " " + name);
  }
  for (const Setting& d : settings) {
    const Value* v = s.find(d.name);
    if (v == nullptr) throw SettingError(d.name, "missing");
    if (auto why = d.rejection(*v)) throw SettingError(d.name + why->where, why->reason);
  }
  if (check) check(s);
}

}  // namespace rfsitl::config
