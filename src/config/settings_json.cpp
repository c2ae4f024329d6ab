#include "rfsitl/config/settings_json.hpp"

#include <type_traits>

namespace rfsitl::config {
namespace {

// [{"t": 0, "x": 1}, ...]: the items as given, fields in declaration order.
nlohmann::json records_json(const Records& items) {
  nlohmann::json j = nlohmann::json::array();
  for (const Record& r : items) {
    nlohmann::json item = nlohmann::json::object();
    for (const auto& [name, value] : r) item[name] = value;
    j.push_back(std::move(item));
  }
  return j;
}

// The items of list setting `d` from a JSON array of objects of numbers. Keys
// are taken in declaration order, so that a round trip gives equal records;
// required fields and limits are left to validate(), which names the item.
Records records_from_json(const Setting& d, const nlohmann::json& j) {
  if (!j.is_array()) throw SettingError(d.name, "expected a list, got " + j.dump());
  Records out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const nlohmann::json& item = j[i];
    const std::string at = d.name + "[" + std::to_string(i) + "]";
    if (!item.is_object()) throw SettingError(at, "expected an object, got " + item.dump());
    for (const auto& kv : item.items()) {
      if (d.items.find(kv.key()) == nullptr) {
        throw SettingError(at + "." + kv.key(),
                           "unknown key (allowed: " + d.items.field_names() + ")");
      }
      if (!kv.value().is_number()) {
        throw SettingError(at + "." + kv.key(), "expected a number, got " + kv.value().dump());
      }
    }
    Record r;
    for (const RecordField& f : d.items.fields) {
      const auto v = item.find(f.name);
      if (v != item.end()) r.set(f.name, v->get<double>());
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace

nlohmann::json to_json(const Value& value) {
  return std::visit(
      [](const auto& v) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Records>) {
          return records_json(v);
        } else {
          return v;
        }
      },
      value);
}

nlohmann::json to_json(const Settings& s) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& entry : s) j[entry.first] = to_json(entry.second);
  return j;
}

nlohmann::json component_json(const ComponentInfo& c) {
  nlohmann::json settings = nlohmann::json::array();
  for (const Setting& d : c.settings) {
    settings.push_back({{"name", d.name},
                        {"type", type_name(d.type)},
                        {"default", to_json(d.default_value)},
                        {"unit", d.unit},
                        {"limits", d.limits_text()},
                        {"choices", d.choices},
                        {"doc", d.doc}});
  }
  return {{"kind", c.kind}, {"name", c.name}, {"doc", c.doc}, {"settings", std::move(settings)}};
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
      case ValueType::kRecords:
        s.set(d.name, records_from_json(d, v));
        break;
    }
  }
  component.validate(s);
  return s;
}

}  // namespace rfsitl::config
