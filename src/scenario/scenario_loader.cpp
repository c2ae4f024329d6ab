// Scenario files: YAML in, a validated Scenario out, and every mistake reported as
// "<source>:<line>: <dotted.key>: <reason>" so that a user can fix it without reading
// this code. Reading checks syntax, keys and types, and the ranges of integers (they
// must fit their fields before being narrowed); validate() checks every range and
// cross-field rule on any Scenario (a file, or defaults plus command-line overrides),
// naming lines through the key -> line table that reading fills in.
#include "rfsitl/scenario/scenario_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <concepts>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/config/setting.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "scenario_rules.hpp"

namespace rfsitl::scenario {
namespace {

using namespace detail;

// Far beyond any real scenario (250 nodes and thousands of traffic lines are a
// few hundred KiB); keeps a wrong path such as /dev/zero from eating memory.
constexpr std::size_t kMaxScenarioBytes = std::size_t{16} << 20;

// ---- YAML scalars -------------------------------------------------------------------------

int line_of(const YAML::Node& n) {
  return n.Mark().is_null() ? 0 : n.Mark().line + 1;
}

std::string kind_of(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  return n.IsSequence() ? "a list" : n.IsMap() ? "a mapping" : "nothing";
}

// A decimal number as YAML plain scalars write them: "1e6", "-78.789", "+3".
std::optional<double> to_real(std::string_view t) {
  if (t.size() > 1 && t[0] == '+' && t[1] != '-') t.remove_prefix(1);
  double v = 0;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || res.ec != std::errc{} || res.ptr != t.data() + t.size()) return std::nullopt;
  return v;
}

// The value under a dotted key; undefined when the key is absent.
struct Entry {
  YAML::Node value;
  std::string key;
  explicit operator bool() const { return value.IsDefined(); }
};

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

// Any finite number; validate() applies the setting's own range.
double real(const Context& c, const Entry& e) {
  const std::string t = scalar(c, e, "a number", true);
  const auto v = to_real(t);
  if (!v) c.fail(e.key, "expected a number, got '" + t + "'");
  c.check(*v, e.key, kFinite);
  return *v;
}

// 1000, +1000 and 1e3 are the same integer; 1.5 is not an integer.
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

// ---- YAML structure -----------------------------------------------------------------------

// One mapping being read. Every key the code asks for is known; finish() turns any other
// key into an error, so that a typo such as `tick_sample` is never silently ignored.
class Section {
 public:
  Section(Context& c, const Entry& at) : c_(c), at_(at) {
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
    map_ = at.value;
  }

  // The value under `leaf`; undefined when absent.
  Entry take(std::string_view leaf) {
    known_.push_back(leaf);
    Entry e{YAML::Node(YAML::NodeType::Undefined), child(leaf)};
    for (const auto& kv : map_) {
      if (kv.first.Scalar() == leaf) e.value = kv.second;
    }
    return e;
  }
  Entry require(std::string_view leaf) {
    Entry e = take(leaf);
    if (!e) c_.fail(e.key, "required");
    return e;
  }

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

  // Keys present but never asked for (so far).
  std::vector<std::string> unknown_keys() const {
    std::vector<std::string> out;
    for (const auto& kv : map_) {
      if (!is_one_of(kv.first.Scalar(), known_)) out.push_back(kv.first.Scalar());
    }
    return out;
  }

  void finish() const {
    for (const auto& kv : map_) {
      if (is_one_of(kv.first.Scalar(), known_)) continue;
      c_.fail(child(kv.first.Scalar()), "unknown key (allowed " +
                                            (at_.key.empty() ? "at top level" : "in " + at_.key) +
                                            ": " + join(known_) + ")");
    }
  }

 private:
  std::string child(std::string_view leaf) const {
    return at_.key.empty() ? std::string(leaf) : at_.key + "." + std::string(leaf);
  }

  Context& c_;
  Entry at_;
  YAML::Node map_{YAML::NodeType::Map};
  std::vector<std::string_view> known_;
};

// Calls read(item) for every entry of a list; absent or empty means no entries.
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

// "43.0008 -78.789 10" or "43.0008, -78.789, 10": exactly three numbers, else nullopt.
std::optional<GeodeticPosition> three_numbers(std::string t) {
  std::replace(t.begin(), t.end(), ',', ' ');
  GeodeticPosition g;
  int used = 0;
  const int n = std::sscanf(t.c_str(), "%lf %lf %lf %n", &g.lat_deg, &g.lon_deg, &g.alt_m, &used);
  return n == 3 && static_cast<std::size_t>(used) == t.size() ? std::optional(g) : std::nullopt;
}

// {lat, lon, alt}, {x, y, z} or "lat lon alt" (as on the location feed). No position
// (absent or empty) means the node is placed by its location feed. Ranges: validate().
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

// ---- sections ----------------------------------------------------------------------------

void read_time(Context& c, const Entry& at, TimingConfig& t) {
  Section sec(c, at);
  if (const Entry mode = sec.take("mode")) {
    const std::string m = text(c, mode);
    c.check_name(m, mode.key, kTimeModes);
    t.mode = m == "virtual" ? TimeMode::kVirtual : TimeMode::kRealTime;
  }
  sec.get("speed", t.speed);
  sec.get("sample_rate_hz", t.sample_rate_hz);
  sec.get("tick_samples", t.tick_samples, kTickSamples);
  sec.get("duration_s", t.duration_s);
  sec.finish();
}

void read_ports(Context& c, const Entry& at, PortConfig& p) {
  Section sec(c, at);
  sec.get("bind", p.bind_address);
  sec.get("net_base", p.net_base, kPort);
  sec.get("loc_base", p.loc_base, kPort);
  sec.finish();
}

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

// The settings `info` declares, read from `sec` into `settings` (which holds
// their values so far), then checked with the component's own rules. `others`
// (components of the same kind) name the owner of a key this one lacks.
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

// `type` picks a registered PHY; a type other than the current one starts from
// that PHY's defaults (so a node inherits the scenario's PHY settings only when
// its type is the same). `process` and `tx_queue_frames` are every PHY's; the
// rest are the PHY's declared settings.
void read_phy(Context& c, const Entry& at, PhyChoice& p) {
  Section sec(c, at);
  if (const Entry type = sec.take("type")) {
    const std::string t = text(c, type);
    c.check_name(t, type.key, phy::known_phy_types());
    if (t != p.type) {
      p.type = t;
      p.settings = PhyChoice::phy_defaults(t);
    }
  }
  if (const Entry process = sec.take("process")) {
    const std::string name = text(c, process);
    c.check_name(name, process.key, kProcesses);
    p.process = name == "child" ? Process::kChild : Process::kInline;
  }
  sec.get("tx_queue_frames", p.tx_queue_frames, kTxQueue);
  std::vector<const config::ComponentInfo*> phys;
  for (const phy::PhyComponent& other : phy::phy_components()) phys.push_back(&other.info);
  read_declared(c, sec, at, p.component().info, phys, p.settings);
}

// `mobility: {type: orbit, radius_m: 50}`: a registered model and its settings.
std::optional<MobilityChoice> read_mobility(Context& c, const Entry& at) {
  if (!at || at.value.IsNull()) return std::nullopt;
  Section sec(c, at);
  const Entry type = sec.require("type");
  MobilityChoice m{text(c, type), {}};
  std::vector<const config::ComponentInfo*> models;
  std::vector<std::string> names;
  for (const auto& model : position::mobility::mobility_components()) {
    models.push_back(&model.info);
    names.push_back(model.info.name);
  }
  c.check_name(m.type, type.key, names);
  const config::ComponentInfo& info = position::mobility::find_mobility(m.type)->info;
  m.settings = info.defaults();
  read_declared(c, sec, at, info, models, m.settings);
  return m;
}

// `position: {source: mavlink, endpoint: ..., rate_hz: 10}`: a live source and
// its declared settings. A node's may add `start: {x, y, z}`
// (or lat/lon/alt), where the node is until its source first reports.
PositionSourceChoice read_source(Context& c, const Entry& at, std::optional<Position>* start) {
  Section sec(c, at);
  const Entry type = sec.require("source");
  PositionSourceChoice p{text(c, type), {}};
  std::vector<std::string> names;
  std::vector<const config::ComponentInfo*> sources;
  for (const auto& component : position::position_source_components()) {
    names.push_back(component.info.name);
    sources.push_back(&component.info);
  }
  c.check_name(p.type, type.key, names);
  if (start != nullptr) *start = read_position(c, sec.take("start"));
  const config::ComponentInfo& info = position::find_position_source(p.type)->info;
  p.settings = info.defaults();
  read_declared(c, sec, at, info, sources, p.settings);
  return p;
}

void read_channel(Context& c, const Entry& at, ChannelConfig& ch) {
  Section sec(c, at);
  sec.get("model", ch.model);
  sec.get("path_loss_exponent", ch.path_loss_exponent);
  const Entry variance = sec.take("noise_variance");
  const Entry power_db = sec.take("noise_power_db");
  // Two spellings of one quantity: accepting both would silently prefer one of them.
  if (variance && power_db) {
    c.fail(power_db.key, "conflicts with channel.noise_variance (line " +
                             std::to_string(c.line(variance.key)) + "); give only one");
  }
  if (variance) ch.noise_variance = real(c, variance);
  if (power_db) {
    const double db = real(c, power_db);
    c.check(db, power_db.key, kNoisePowerDb);
    ch.noise_variance = std::pow(10.0, db / 10.0);
  }
  sec.get("shared_noise", ch.shared_noise);
  if (const Entry origin = sec.take("origin")) {
    const auto p = read_position(c, origin);
    if (!p || !std::holds_alternative<GeodeticPosition>(*p)) {
      c.fail(origin.key, "must be a geodetic position {lat, lon, alt}");
    }
    ch.origin = std::get<GeodeticPosition>(*p);
  }
  sec.finish();
}

void read_engine(Context& c, const Entry& at, EngineConfig& e) {
  Section sec(c, at);
  sec.get("threads", e.threads, kThreads);
  sec.get("skip_idle_receivers", e.skip_idle_receivers);
  sec.get("stats_interval_s", e.stats_interval_s);
  sec.get("mobility_update_s", e.mobility_update_s);
  sec.finish();
}

void read_external(Context& c, const Entry& at, ExternalConfig& e) {
  Section sec(c, at);
  sec.get("socket", e.socket_path);
  sec.get("reply_timeout_s", e.reply_timeout_s);
  sec.get("start_timeout_s", e.start_timeout_s);
  sec.get("restart_children", e.restart_children);
  sec.finish();
}

// Node ids and traffic endpoints are required although the structs have defaults: a
// silent default would invent a node the user never named.
NodeId node_id(Context& c, Section& sec, std::string_view leaf, IntLimit lim) {
  return static_cast<NodeId>(integer(c, sec.require(leaf), lim));
}

// A node's `phy` starts from the scenario's and overrides the keys it names.
NodeConfig read_node(Context& c, const Entry& at, const PhyChoice& scenario_phy) {
  Section sec(c, at);
  NodeConfig n;
  n.id = node_id(c, sec, "id", kNodeIdLimit);
  // `position:` is where the node starts, or (with `source:`) where its
  // positions come from.
  const Entry position = sec.take("position");
  if (const YAML::Node v = position.value; position && v.IsMap() && v["source"]) {
    n.source = read_source(c, position, &n.initial_position);
  } else {
    n.initial_position = read_position(c, position);
  }
  n.mobility = read_mobility(c, sec.take("mobility"));
  if (const Entry phy = sec.take("phy")) {
    n.phy = scenario_phy;
    read_phy(c, phy, *n.phy);
  }
  sec.finish();
  return n;
}

TrafficItem read_traffic_item(Context& c, const Entry& at) {
  Section sec(c, at);
  TrafficItem t;
  sec.get("at_s", t.at_s);
  t.src = node_id(c, sec, "src", kNodeIdLimit);
  t.dst = node_id(c, sec, "dst", kDstLimit);
  sec.get("size_bytes", t.size_bytes, kSize);
  sec.get("repeat", t.repeat, kRepeat);
  sec.get("interval_s", t.interval_s);
  sec.finish();
  return t;
}

// The settings a scenario file and the command line share (everything but nodes
// and traffic), read from the top-level mapping into `s`; keys not given keep
// their value.
void read_settings(Context& c, Section& sec, Scenario& s) {
  sec.get("name", s.name);
  sec.get("seed", s.seed, kSeed);
  read_time(c, sec.take("time"), s.timing);
  read_ports(c, sec.take("ports"), s.ports);
  read_phy(c, sec.take("phy"), s.phy);
  read_channel(c, sec.take("channel"), s.channel);
  read_engine(c, sec.take("engine"), s.engine);
  read_external(c, sec.take("external"), s.external);
}

Scenario read_scenario(Context& c, const YAML::Node& root) {
  c.record("", std::max(line_of(root), 1));  // "nodes: required" points at the document
  if (!root.IsMap() && !root.IsNull())
    c.fail("(top level)", "expected a mapping, got " + kind_of(root));
  Section sec(c, Entry{root, ""});
  Scenario s;
  read_settings(c, sec, s);
  if (const Entry position = sec.take("position")) {
    s.position_source = read_source(c, position, nullptr);
  }
  const Entry nodes = sec.take("nodes");
  const Entry traffic = sec.take("traffic");
  sec.finish();  // a misspelt key (`nodez:`) is named before `nodes` is missed
  if (!nodes) c.fail("nodes", "required");
  for_each_item(c, nodes, [&](const Entry& e) { s.nodes.push_back(read_node(c, e, s.phy)); });
  for_each_item(c, traffic, [&](const Entry& e) { s.traffic.push_back(read_traffic_item(c, e)); });
  return s;
}

}  // namespace

Scenario parse_scenario(std::string_view yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    const bool marked = !e.mark.is_null();
    throw make_error(source, marked ? e.mark.line + 1 : 0, "YAML syntax",
                     e.msg + (marked ? " (column " + std::to_string(e.mark.column + 1) + ")" : ""));
  }
  Context context(source);
  Scenario s = read_scenario(context, root);
  validate(s, context);
  return s;
}

Scenario load_scenario_file(const std::string& path) {
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  const auto unreadable = [&path] {
    return ScenarioError(path + ": cannot read scenario file: " + std::strerror(errno));
  };
  if (!file) throw unreadable();
  std::string contents;
  std::array<char, 8192> buf{};
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), file.get())) > 0;) {
    contents.append(buf.data(), n);
    if (contents.size() > kMaxScenarioBytes) {  // e.g. /dev/zero: never a scenario
      throw ScenarioError(path + ": cannot read scenario file: larger than " +
                          std::to_string(kMaxScenarioBytes >> 20) + " MiB");
    }
  }
  if (std::ferror(file.get())) throw unreadable();  // e.g. a directory: EISDIR
  Scenario s = parse_scenario(contents, path);
  s.source_dir = std::filesystem::path(path).parent_path().string();
  return s;
}

void validate_scenario(const Scenario& s) {
  validate(s, Context("scenario"));
}

void apply_setting(Scenario& s, std::string_view dotted_key, std::string_view value,
                   const std::string& source) {
  // The setting as the one-entry document a file would hold ("a.b: v"), read by
  // the file's own readers so that both paths share every rule.
  YAML::Node root(YAML::NodeType::Map);
  YAML::Node at = root;
  std::string_view rest = dotted_key;
  for (std::size_t dot; (dot = rest.find('.')) != std::string_view::npos;) {
    at.reset(at[std::string(rest.substr(0, dot))]);  // rebinds; `=` would copy into it
    rest.remove_prefix(dot + 1);
  }
  at[std::string(rest)] = std::string(value);
  Context c(source);
  Section sec(c, Entry{root, ""});
  read_settings(c, sec, s);
  sec.finish();
  validate(s, c);
}

}  // namespace rfsitl::scenario
