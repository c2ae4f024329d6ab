#include "rfsitl/config/record.hpp"

#include <algorithm>

namespace rfsitl::config {

Record::Record(std::initializer_list<std::pair<std::string, double>> fields) {
  for (const auto& f : fields) set(f.first, f.second);
}

const double* Record::find(std::string_view name) const {
  const auto it = std::find_if(fields_.begin(), fields_.end(),
                               [name](const auto& kv) { return kv.first == name; });
  return it == fields_.end() ? nullptr : &it->second;
}

void Record::set(std::string_view name, double value) {
  const auto it = std::find_if(fields_.begin(), fields_.end(),
                               [name](const auto& kv) { return kv.first == name; });
  if (it != fields_.end()) {
    it->second = value;
  } else {
    fields_.emplace_back(std::string(name), value);
  }
}

std::string to_text(const Records& items) {
  std::string out = "[";
  for (const Record& r : items) {
    out += out.size() > 1 ? ", {" : "{";
    bool first = true;
    for (const auto& [name, value] : r) {
      out.append(first ? "" : ", ").append(name).append(": ").append(number_text(value));
      first = false;
    }
    out += "}";
  }
  return out + "]";
}

const RecordField* RecordShape::find(std::string_view name) const {
  const auto it = std::find_if(fields.begin(), fields.end(),
                               [name](const RecordField& f) { return f.name == name; });
  return it == fields.end() ? nullptr : &*it;
}

std::string RecordShape::field_names() const {
  std::string out;
  for (const RecordField& f : fields) out.append(out.empty() ? "" : ", ").append(f.name);
  return out;
}

std::string RecordShape::count_text() const {
  constexpr std::size_t kAny = std::numeric_limits<std::size_t>::max();
  if (max_items == kAny) return min_items == 0 ? "" : ">= " + std::to_string(min_items) + " items";
  return std::to_string(min_items) + ".." + std::to_string(max_items) + " items";
}

std::optional<Rejection> RecordShape::rejection(const Records& items) const {
  if (items.size() < min_items) {
    return Rejection{"", "must hold at least " + std::to_string(min_items) +
                             (min_items == 1 ? " item" : " items") + ", got " +
                             std::to_string(items.size())};
  }
  if (items.size() > max_items) {
    return Rejection{"", "must hold at most " + std::to_string(max_items) + " items, got " +
                             std::to_string(items.size())};
  }
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string at = "[" + std::to_string(i) + "]";
    for (const auto& [name, value] : items[i]) {
      const RecordField* f = find(name);
      if (f == nullptr)
        return Rejection{at + "." + name, "unknown key (allowed: " + field_names() + ")"};
      if (auto why = f->range.reject_reason(value)) return Rejection{at + "." + name, *why};
    }
    for (const RecordField& f : fields) {
      if (f.required && items[i].find(f.name) == nullptr) {
        return Rejection{at + "." + f.name, "required"};
      }
    }
  }
  return std::nullopt;
}

}  // namespace rfsitl::config
