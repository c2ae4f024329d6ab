#include "rfsitl/config/settings_table.hpp"

namespace rfsitl::config {
namespace {

std::string_view short_type(ValueType t) {
  switch (t) {
    case ValueType::kBool:
      return "bool";
    case ValueType::kInteger:
      return "integer";
    case ValueType::kReal:
      return "real";
    case ValueType::kText:
      return "text";
    case ValueType::kRecords:
      break;
  }
  return "list";
}

// A table cell: '|' would end the cell early.
std::string cell(std::string s) {
  for (std::size_t at = 0; (at = s.find('|', at)) != std::string::npos; at += 2) s.insert(at, "\\");
  return s;
}

std::string code(const std::string& s) {
  return s.empty() ? "" : "`" + cell(s) + "`";
}

// What an item of list setting `s` may give, one row per field.
std::string item_table(const Setting& s) {
  std::string out = "\nEach item of `" + s.name + "`:\n\n";
  out += "| field | unit | default | allowed | meaning |\n";
  out += "|---|---|---|---|---|\n";
  for (const RecordField& f : s.items.fields) {
    const std::string shown = f.required        ? "required"
                              : f.default_value ? code(number_text(*f.default_value))
                                                : "";
    out += "| `" + f.name + "` | " + cell(f.unit) + " | " + shown + " | " + cell(f.range.text()) +
           " | " + cell(f.doc) + " |\n";
  }
  return out;
}

}  // namespace

std::string settings_table(const ComponentInfo& component) {
  if (component.settings.empty()) return "(no settings)\n";
  std::string out = "| setting | type | unit | default | allowed | meaning |\n";
  out += "|---|---|---|---|---|---|\n";
  std::string items;
  for (const Setting& s : component.settings) {
    out += "| `" + s.name + "` | " + std::string(short_type(s.type)) + " | " + cell(s.unit) +
           " | " + code(to_text(s.default_value)) + " | " + cell(s.limits_text()) + " | " +
           cell(s.doc) + " |\n";
    if (s.type == ValueType::kRecords) items += item_table(s);
  }
  return out + items;
}

}  // namespace rfsitl::config
