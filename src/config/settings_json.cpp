#include "rfsitl/config/settings_json.hpp"

namespace rfsitl::config {

nlohmann::json to_json(const Settings& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& entry : s) {
    std::visit([&j, &entry](const auto& v) { j[entry.first] = v; }, entry.second);
  }
  return j;
}

Settings settings_from_json(const ComponentInfo& component, const nlohmann::json& j) {
  if (!j.is_object()) throw SettingError("", "expected a JSON object, got " + j.dump());
  for (const auto& [key, v] : j.items()) {
    if (component.find(key) == nullptr) {
      throw SettingError(key, "not a setting of " + component.kind + " " + component.name);
    }
  }
  Settings s;  // in declaration order, as the component's defaults() are
  for (const Setting& d : component.settings) {
    const auto it = j.find(d.name);
    if (it == j.end()) continue;  // validate() names it
    const nlohmann::json& v = *it;
    const auto wrong = [&] {
      return SettingError(d.name,
                          "expected " + std::string(type_name(d.type)) + ", got " + v.dump());
    };
    switch (d.type) {
      case ValueType::kBool:
        if (!v.is_boolean()) throw wrong();
        s.set(d.name, v.get<bool>());
        break;
      case ValueType::kInteger:
        if (!v.is_number_unsigned()) throw wrong();
        s.set(d.name, v.get<std::uint64_t>());
        break;
      case ValueType::kReal:
        if (!v.is_number()) throw wrong();
        s.set(d.name, v.get<double>());
        break;
      case ValueType::kText:
        if (!v.is_string()) throw wrong();
        s.set(d.name, v.get<std::string>());
        break;
    }
  }
  component.validate(s);
  return s;
}

}  // namespace rfsitl::config
