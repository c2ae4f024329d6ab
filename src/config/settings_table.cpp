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
      break;
  }
  return "text";
}

// A table cell: '|' would end the cell early.
std::string cell(std::string s) {
  for (std::size_t at = 0; (at = s.find('|', at)) != std::string::npos; at += 2) s.insert(at, "\\");
  return s;
}

}  // namespace

std::string settings_table(const ComponentInfo& component) {
  if (component.settings.empty()) return "(no settings)\n";
  std::string out = "| setting | type | unit | default | allowed | meaning |\n";
  out += "|---|---|---|---|---|---|\n";
  for (const Setting& s : component.settings) {
    const std::string shown = to_text(s.default_value);
    out += "| `" + s.name + "` | " + std::string(short_type(s.type)) + " | " + cell(s.unit) +
           " | " + (shown.empty() ? "" : "`" + cell(shown) + "`") + " | " + cell(s.limits_text()) +
           " | " + cell(s.doc) + " |\n";
  }
  return out;
}

}  // namespace rfsitl::config
