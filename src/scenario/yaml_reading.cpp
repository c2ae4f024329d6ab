#include "yaml_reading.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <utility>

namespace rfsitl::scenario::detail {
namespace {

// A decimal number as YAML plain scalars write them: "1e6", "-78.789", "+3".
std::optional<double> to_real(std::string_view t) {
  if (t.size() > 1 && t[0] == '+' && t[1] != '-') t.remove_prefix(1);
  double v = 0;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || res.ec != std::errc{} || res.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

// A quoted scalar is a string in YAML, so where a number or boolean is expected
// (`plain_only`) it is a type error, not a number in disguise.
std::string scalar(const Context& c, const Entry& e, const std::string& expected, bool plain_only) {
  const YAML::Node& v = e.value;
  if (!v.IsScalar()) c.fail(e.key, "expected " + expected + ", got " + kind_of(v));
  if (plain_only && v.Tag() == "!") {
    c.fail(e.key, "expected " + expected + ", got the string \"" + v.Scalar() + "\"");
  }
  return v.Scalar();
}

// "43.0008 -78.789 10" or "43.0008, -78.789, 10": exactly three numbers, else nullopt.
std::optional<GeodeticPosition> three_numbers(std::string t) {
  std::replace(t.begin(), t.end(), ',', ' ');
  GeodeticPosition g;
  int used = 0;
  const int n = std::sscanf(t.c_str(), "%lf %lf %lf %n", &g.lat_deg, &g.lon_deg, &g.alt_m, &used);
  return n == 3 && static_cast<std::size_t>(used) == t.size() ? std::optional(g) : std::nullopt;
}

}  // namespace

int line_of(const YAML::Node& n) {
  return n.Mark().is_null() ? 0 : n.Mark().line + 1;
}

std::string kind_of(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  return n.IsSequence() ? "a list" : n.IsMap() ? "a mapping" : "nothing";
}

std::string text(const Context& c, const Entry& e) {
  return scalar(c, e, "a string", false);
}

bool boolean(const Context& c, const Entry& e) {
  std::string t = scalar(c, e, "true or false", true);
  for (char& ch : t) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (t == "true" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "no" || t == "off") return false;
  c.fail(e.key, "expected true or false, got '" + e.value.Scalar() + "'");
}

double real(const Context& c, const Entry& e) {
  const std::string t = scalar(c, e, "a number", true);
  const auto v = to_real(t);
  if (!v) c.fail(e.key, "expected a number, got '" + t + "'");
  c.check(*v, e.key, kFinite);
  return *v;
}

std::uint64_t integer(const Context& c, const Entry& e, IntLimit lim) {
  const std::string t = scalar(c, e, "an integer", true);
  std::uint64_t u = 0;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), u);
  if (res.ec != std::errc{} || res.ptr != t.data() + t.size()) {
    const auto v = to_real(t);
    if (!v) c.fail(e.key, "expected an integer, got '" + t + "'");
    if (*v != std::floor(*v)) c.fail(e.key, "must be an integer, got " + t);
    if (!(*v >= 0 && *v < 0x1p64)) c.fail(e.key, lim.describe() + ", got " + t);
    u = static_cast<std::uint64_t>(*v);
  }
  c.check(u, e.key, lim);
  return u;
}

Section::Section(Context& c, const Entry& at) : c_(c), at_(at) {
  if (!at || at.value.IsNull()) return;  // absent, or `key:` with nothing: all defaults
  if (!at.value.IsMap()) {
    c.fail(at.key, "expected a mapping (key: value), got " + kind_of(at.value));
  }
  std::map<std::string, int, std::less<>> seen;
  for (const auto& kv : at.value) {
    if (!kv.first.IsScalar()) c.fail(at.key, "keys must be plain names");
    const std::string key = child(kv.first.Scalar());
    // The key's line, also for its value's errors: yaml-cpp marks an empty value at
    // the next token, which may be lines further down.
    const auto [it, fresh] = seen.emplace(key, line_of(kv.first));
    c.record(key, line_of(kv.first));
    if (!fresh) c.fail(key, "duplicate key (first at line " + std::to_string(it->second) + ")");
  }
  map_.reset(at.value);  // rebinds (`=` would merge the document's nodes into map_'s)
}

Entry Section::take(std::string_view leaf) {
  known_.push_back(leaf);
  // Copies of a YAML::Node share the node; assigning one to a node that
  // exists (`=`) merges the whole document's node set into it, for every key
  // read: quadratic in the file's size. The constructor made keys unique.
  for (const auto& kv : map_) {
    if (kv.first.Scalar() == leaf) return Entry{kv.second, child(leaf)};
  }
  return Entry{YAML::Node(YAML::NodeType::Undefined), child(leaf)};
}

Entry Section::require(std::string_view leaf) {
  Entry e = take(leaf);
  if (!e) c_.fail(e.key, "required");
  return e;
}

std::vector<std::string> Section::unknown_keys() const {
  std::vector<std::string> out;
  for (const auto& kv : map_) {
    if (!is_one_of(kv.first.Scalar(), known_)) out.push_back(kv.first.Scalar());
  }
  return out;
}

void Section::finish() const {
  for (const auto& kv : map_) {
    if (is_one_of(kv.first.Scalar(), known_)) continue;
    c_.fail(child(kv.first.Scalar()), "unknown key (allowed " +
                                          (at_.key.empty() ? "at top level" : "in " + at_.key) +
                                          ": " + join(known_) + ")");
  }
}

std::string Section::child(std::string_view leaf) const {
  return at_.key.empty() ? std::string(leaf) : at_.key + "." + std::string(leaf);
}

std::optional<Position> read_position(Context& c, const Entry& e) {
  if (!e || e.value.IsNull()) return std::nullopt;
  if (e.value.IsScalar()) {
    const auto g = three_numbers(text(c, e));
    if (!g) c.fail(e.key, "expected 'lat lon alt' (three numbers), got '" + e.value.Scalar() + "'");
    return *g;
  }
  if (!e.value.IsMap()) {
    c.fail(e.key, "expected {lat, lon, alt}, {x, y, z} or 'lat lon alt', got " + kind_of(e.value));
  }
  Section sec(c, e);
  const Entry lat = sec.take("lat"), lon = sec.take("lon"), alt = sec.take("alt");
  const Entry x = sec.take("x"), y = sec.take("y"), z = sec.take("z");
  sec.finish();
  const bool geodetic = lat || lon || alt;
  if (geodetic && (x || y || z)) c.fail(e.key, "mixes lat/lon/alt with x/y/z; use one form");
  if (geodetic) {
    if (!lat || !lon) c.fail(e.key, "needs lat and lon (alt defaults to 0)");
    return GeodeticPosition{real(c, lat), real(c, lon), alt ? real(c, alt) : 0.0};
  }
  if (!x || !y) c.fail(e.key, "needs lat and lon (alt defaults to 0) or x and y (z defaults to 0)");
  return LocalPosition{real(c, x), real(c, y), z ? real(c, z) : 0.0};
}

namespace {

// A list setting's items: each a mapping of the declared numeric fields, every
// field checked as it is read, so that an error names the item, the field and
// their own line (`points[1].t`), not the list's.
config::Records read_records(Context& c, const Entry& list, const config::RecordShape& shape) {
  config::Records items;
  if (list.value.IsNull()) return items;  // `points:` with nothing: the count rule names it
  for_each_item(c, list, [&](const Entry& item) {
    Section sec(c, item);
    config::Record r;
    for (const config::RecordField& f : shape.fields) {
      const Entry field = sec.take(f.name);
      if (!field) {
        if (f.required) c.fail(field.key, "required");
        continue;
      }
      const double v = real(c, field);
      if (const auto why = f.range.reject_reason(v)) c.fail(field.key, *why);
      r.set(f.name, v);
    }
    sec.finish();
    items.push_back(std::move(r));
  });
  return items;
}

// A value of a component's declared setting, with the declaration's type and limits.
config::Value read_value(Context& c, const Entry& e, const config::Setting& d) {
  config::Value v;
  switch (d.type) {
    case config::ValueType::kBool:
      v = boolean(c, e);
      break;
    case config::ValueType::kInteger:
      v = integer(c, e, kAnyInteger);
      break;
    case config::ValueType::kReal:
      v = real(c, e);
      break;
    case config::ValueType::kText:
      v = text(c, e);
      break;
    case config::ValueType::kRecords:
      v = read_records(c, e, d.items);
      break;
  }
  if (const auto why = d.rejection(v)) c.fail(e.key + why->where, why->reason);
  return v;
}

}  // namespace

void read_declared(Context& c, Section& sec, const Entry& at, const config::ComponentInfo& info,
                   const std::vector<const config::ComponentInfo*>& others,
                   config::Settings& settings) {
  for (const config::Setting& d : info.settings) {
    if (const Entry e = sec.take(d.name)) settings.set(d.name, read_value(c, e, d));
  }
  // A setting of another component is the likeliest mistake: say whose it is.
  for (const std::string& key : sec.unknown_keys()) {
    for (const config::ComponentInfo* other : others) {
      if (other->find(key) == nullptr) continue;
      std::string own;
      for (const config::Setting& d : info.settings) own += (own.empty() ? "" : ", ") + d.name;
      c.fail(at.key + "." + key, "is a setting of " + info.kind + " type " + other->name +
                                     ", not of " + info.name + " (whose settings are: " + own +
                                     ")");
    }
  }
  sec.finish();
  try {
    info.validate(settings);
  } catch (const config::SettingError& e) {
    c.fail(e.key().empty() ? at.key : at.key + "." + e.key(), e.what());
  }
}

}  // namespace rfsitl::scenario::detail
