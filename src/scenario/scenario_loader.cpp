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

#include "channel_reading.hpp"
#include "rfsitl/config/setting.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/mac_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/link_budget_of.hpp"
#include "rfsitl/scenario/mobility_of.hpp"
#include "scenario_rules.hpp"
#include "yaml_reading.hpp"

namespace rfsitl::scenario {
namespace {

using namespace detail;

// Far beyond any real scenario (250 nodes and thousands of traffic lines are a
// few hundred KiB); keeps a wrong path such as /dev/zero from eating memory.
constexpr std::size_t kMaxScenarioBytes = std::size_t{16} << 20;

// ---- sections ----------------------------------------------------------------------------

// `tick_us`: the tick by its duration, at the sample rate known when it is read
// (the same section's or the current one), so that a 20 Msps scenario can ask
// for 100 us ticks instead of counting 2000 samples. It must come to a whole
// number of samples: a tick of 333.3 samples would make the clock drift.
std::uint32_t tick_samples_of_us(Context& c, const Entry& us, double sample_rate_hz) {
  const double v = real(c, us);
  c.check(v, us.key, kPositive);
  if (!(sample_rate_hz > 0.0)) {
    c.fail(us.key, "needs a sample rate > 0, got " + fmt(sample_rate_hz) + " Hz");
  }
  const double n = v * 1e-6 * sample_rate_hz;
  const double whole = std::round(n);
  // 1e-9 relative: 0.1 us at 20e6 Hz reads back as 1.9999999999999998 samples.
  if (std::abs(n - whole) > 1e-9 * std::max(1.0, n)) {
    c.fail(us.key, fmt(v) + " us at " + fmt(sample_rate_hz) + " Hz is " + fmt(n) +
                       " samples, not a whole number (use tick_samples, or a duration that is)");
  }
  // Compared as doubles: 1e30 samples must not be converted to an integer first.
  if (whole < static_cast<double>(kTickSamples.lo) ||
      whole > static_cast<double>(kTickSamples.hi)) {
    c.fail(us.key, fmt(v) + " us at " + fmt(sample_rate_hz) + " Hz is " + fmt(whole) +
                       " samples; the tick " + kTickSamples.describe() + " samples");
  }
  return static_cast<std::uint32_t>(whole);
}

void read_time(Context& c, const Entry& at, TimingConfig& t) {
  Section sec(c, at);
  if (const Entry mode = sec.take("mode")) {
    const std::string m = text(c, mode);
    c.check_name(m, mode.key, kTimeModes);
    t.mode = m == "virtual" ? TimeMode::kVirtual : TimeMode::kRealTime;
    t.mode_given_at = c.where(mode.key);
  }
  sec.get("speed", t.speed);
  sec.get("sample_rate_hz", t.sample_rate_hz);
  const Entry samples = sec.take("tick_samples");
  const Entry us = sec.take("tick_us");
  if (samples && us) {
    c.fail(us.key, "give the tick as tick_samples or as tick_us, not both");
  }
  if (samples) t.tick_samples = static_cast<std::uint32_t>(integer(c, samples, kTickSamples));
  if (us) t.tick_samples = tick_samples_of_us(c, us, t.sample_rate_hz);
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
  for (const position::mobility::MobilityComponent& model :
       position::mobility::mobility_components()) {
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
  for (const position::PositionSourceComponent& component :
       position::position_source_components()) {
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

void read_engine(Context& c, const Entry& at, EngineConfig& e) {
  Section sec(c, at);
  sec.get("threads", e.threads, kThreads);
  sec.get("skip_idle_receivers", e.skip_idle_receivers);
  sec.get("stats_interval_s", e.stats_interval_s);
  sec.get("mobility_update_s", e.mobility_update_s);
  sec.finish();
}

void read_ip(Context& c, const Entry& at, IpConfig& ip) {
  Section sec(c, at);
  sec.get("enabled", ip.enabled);
  sec.get("subnet", ip.subnet);
  sec.get("ipv6_prefix", ip.ipv6_prefix);
  sec.get("interface", ip.interface);
  sec.finish();
}

// `mac: {type: csma, cw_min: 31}`: a registered MAC and its settings.
void read_mac(Context& c, const Entry& at, MacChoice& mac) {
  if (!at) return;
  Section sec(c, at);
  std::vector<std::string> names;
  std::vector<const config::ComponentInfo*> macs;
  for (const mac::MacComponent& component : mac::mac_components()) {
    names.push_back(component.info.name);
    macs.push_back(&component.info);
  }
  if (const Entry type = sec.take("type")) {
    const std::string name = text(c, type);
    c.check_name(name, type.key, names);
    if (name != mac.type) mac.settings = mac::find_mac(name)->info.defaults();
    mac.type = name;
  }
  const config::ComponentInfo& info = mac::find_mac(mac.type)->info;
  if (mac.settings.size() == 0) mac.settings = info.defaults();
  read_declared(c, sec, at, info, macs, mac.settings);
}

// `spectrum: {plans: {wifi24: {first_hz: 2.412e9, ...}}}`: each plan starts
// from the one of that name read so far (a command-line override changes one
// key), else from the declared defaults.
void read_spectrum(Context& c, const Entry& at, SpectrumConfig& spectrum) {
  Section sec(c, at);
  if (const Entry plans = sec.take("plans")) {
    Section list(c, plans);  // a mapping of names, each key once
    const std::vector<std::string> names = list.unknown_keys();
    for (const std::string& name : names) {
      const Entry plan = list.take(name);
      if (name.find('/') != std::string::npos) c.fail(plan.key, "a plan's name has no '/'");
      const config::ComponentInfo& info = channel_plan_info();
      const auto known = spectrum.plans.find(name);
      config::Settings settings = known != spectrum.plans.end()
                                      ? channel_plan_fields().settings_of(known->second)
                                      : info.defaults();
      Section psec(c, plan);
      read_declared(c, psec, plan, info, {}, settings);
      spectrum.plans[name] = channel_plan_fields().build(settings);
    }
    list.finish();
  }
  config::Settings settings = spectrum_fields().settings_of(spectrum);
  read_declared(c, sec, at, spectrum_info(), {}, settings);
  spectrum.duplexer_isolation_db = spectrum_fields().build(settings).duplexer_isolation_db;
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
  if (const Entry netns = sec.take("netns")) n.netns = text(c, netns);
  // The rest are the node's tuning keys (spectrum.hpp); none given: the shared band.
  const config::ComponentInfo& tuning = node_tuning_info();
  config::Settings settings = tuning.defaults();
  read_declared(c, sec, at, tuning, {}, settings);
  if (settings != tuning.defaults()) n.tuning = node_tuning_fields().build(settings);
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
  read_channel_and_radio(c, sec.take("channel"), sec.take("radio"), s);
  read_engine(c, sec.take("engine"), s.engine);
  read_external(c, sec.take("external"), s.external);
  read_ip(c, sec.take("ip"), s.ip);
  read_mac(c, sec.take("mac"), s.mac);
  read_spectrum(c, sec.take("spectrum"), s.spectrum);
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
  if (nodes.value.IsScalar()) {
    // `nodes: 64`: the default formation (a grid where every link decodes, ids
    // 1..N, placed once), for scenarios about the channel or the PHY rather
    // than about where the vehicles are.
    c.record(nodes.key, line_of(nodes.value));
    s.nodes = default_formation(integer(c, nodes, kNodeIdLimit), s.channel);
  } else {
    for_each_item(c, nodes, [&](const Entry& e) { s.nodes.push_back(read_node(c, e, s.phy)); });
  }
  for_each_item(c, traffic, [&](const Entry& e) { s.traffic.push_back(read_traffic_item(c, e)); });
  return s;
}

}  // namespace

namespace {

// The data files of channel stages (antenna patterns, traces) are read here,
// once, so that a broken one is refused at load with its own line.
void check_stage_files(const Scenario& s, const Context& c) {
  for (std::size_t i = 0; i < s.channel.stages.size(); ++i) {
    try {
      (void)make_stage(s, i);
    } catch (const std::invalid_argument& e) {
      c.fail("channel.stages[" + std::to_string(i) + "]", e.what());
    }
  }
}

// The same for mobility models, whose traces are files too.
void check_mobility_files(const Scenario& s, const Context& c) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (!s.nodes[i].mobility) continue;
    try {
      (void)make_mobility(s, i, {});
    } catch (const std::exception& e) {
      c.fail("nodes[" + std::to_string(i) + "].mobility", e.what());
    }
  }
}

// The number of the text's last line: a final newline ends that line, it
// does not start another.
int last_line(std::string_view text) {
  const auto newlines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return std::max(1, text.empty() || text.back() == '\n' ? newlines : newlines + 1);
}

Scenario read_document(const YAML::Node& root, const std::string& source,
                       const std::string& source_dir) {
  Context context(source);
  Scenario s = read_scenario(context, root);
  s.source_dir = source_dir;
  validate(s, context);
  check_stage_files(s, context);
  check_mobility_files(s, context);
  return s;
}

Scenario parse_in(std::string_view yaml_text, const std::string& source,
                  const std::string& source_dir) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    const bool marked = !e.mark.is_null();
    // An error found only at the end of the text (a flow `{` or `[` never
    // closed) is marked after its last line: point at the last line instead.
    const int last = last_line(yaml_text);
    const int line = marked ? std::min(e.mark.line + 1, last) : 0;
    const std::string where = !marked ? ""
                              : e.mark.line + 1 > last
                                  ? " (at the end of the file)"
                                  : " (column " + std::to_string(e.mark.column + 1) + ")";
    throw make_error(source, line, "YAML syntax", e.msg + where);
  }
  return read_document(root, source, source_dir);
}

// A JSON value as the YAML a file would hold: strings quoted (so that "5" is
// a string where a number is expected, as in a file), numbers and booleans
// plain. The nodes carry no marks, so errors name keys without lines.
YAML::Node yaml_of(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::object: {
      YAML::Node map(YAML::NodeType::Map);
      for (const auto& [key, value] : j.items()) map[key] = yaml_of(value);
      return map;
    }
    case nlohmann::json::value_t::array: {
      YAML::Node list(YAML::NodeType::Sequence);
      for (const auto& value : j) list.push_back(yaml_of(value));
      return list;
    }
    case nlohmann::json::value_t::string: {
      YAML::Node text(j.get<std::string>());
      text.SetTag("!");
      return text;
    }
    case nlohmann::json::value_t::null:
      return YAML::Node(YAML::NodeType::Null);
    default:
      return YAML::Node(j.dump());  // a number or a boolean, as JSON writes it
  }
}

}  // namespace

Scenario parse_scenario(std::string_view yaml_text, const std::string& source) {
  return parse_in(yaml_text, source, "");
}

Scenario scenario_from_json(const nlohmann::json& document, const std::string& source,
                            const std::string& base_dir) {
  if (!document.is_object()) {
    throw ScenarioError(source + ": a scenario is a mapping of sections, got " +
                        std::string(document.type_name()));
  }
  return read_document(yaml_of(document), source, base_dir);
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
  // Absolute, so that a data file that cannot be read is named by the path
  // really tried, wherever the user ran the command from.
  return parse_in(contents, path,
                  std::filesystem::absolute(path).lexically_normal().parent_path().string());
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
