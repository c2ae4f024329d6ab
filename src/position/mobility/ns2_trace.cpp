#include "rfsitl/position/mobility/ns2_trace.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "trace_text.hpp"

namespace rfsitl::position::mobility {
namespace {

// The longest leg a file can describe: corner to corner of the local frame's
// limits in x and y. A speed that makes even it finite in time keeps every
// arrival time finite.
constexpr double kLongestLegM = 3 * kMaxLocalCoordinateM;

enum class Axis { kX, kY, kZ };

/// A timed statement of one node: setdest, or a jump along one axis.
struct Event {
  double t_s = 0.0;
  bool setdest = false;
  double x_m = 0.0, y_m = 0.0, speed_mps = 0.0;  // setdest
  Axis axis = Axis::kX;                          // set
  double value_m = 0.0;                          // set
};

struct NodeScript {
  LocalPosition initial;
  std::vector<Event> events;
};

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (true) {
    i = s.find_first_not_of(" \t", i);
    if (i == std::string_view::npos) return out;
    const std::size_t end = std::min(s.find_first_of(" \t", i), s.size());
    out.push_back(s.substr(i, end - i));
    i = end;
  }
}

double& coordinate(LocalPosition& p, Axis a) {
  return a == Axis::kX ? p.x_m : a == Axis::kY ? p.y_m : p.z_m;
}

class Ns2Reader {
 public:
  explicit Ns2Reader(TraceParseResult& result) : result_(result) {}

  void line(std::size_t number, std::string_view text) {
    if (detail::is_blank_or_comment(text)) return;
    const std::vector<std::string_view> w = words(text);
    if (w[0] == "$god_") return;
    if (w[0] == "$ns_") return timed(number, w);
    if (w[0].starts_with("$node_(")) return initial(number, w);
    skip(number, "unknown statement " + detail::quote(w[0]) +
                     ": expected $node_(i) set, $ns_ at, or $god_");
  }

  /// Every node's events, in time order, as knots.
  void finish() {
    for (auto& [node, script] : scripts_) result_.tracks.emplace(node, replay(script));
  }

 private:
  // `$node_(i) set X_ 10.0`
  void initial(std::size_t number, const std::vector<std::string_view>& w) {
    if (w.size() != 4 || w[1] != "set") {
      return skip(number, "expected $node_(i) set X_|Y_|Z_ <metres>");
    }
    // Each check reports and stops, so a line is counted once.
    const auto node = node_of(number, w[0]);
    const auto axis = node ? axis_of(number, w[2]) : std::nullopt;
    if (!axis) return;
    if (const auto v = value_of(number, *axis, w[3]))
      coordinate(scripts_[*node].initial, *axis) = *v;
  }

  // `$ns_ at 2.0 "$node_(i) setdest x y speed"` or `... "$node_(i) set X_ v"`
  void timed(std::size_t number, std::vector<std::string_view> w) {
    if (w.size() < 4 || w[1] != "at") return skip(number, "expected $ns_ at <time> \"<command>\"");
    // The command is the quoted rest: take the quotes off its first and last word.
    std::vector<std::string_view> c(w.begin() + 3, w.end());
    if (!c.front().starts_with('"') || !c.back().ends_with('"') ||
        (c.size() == 1 && c.front().size() < 2)) {
      return skip(number, "the command after $ns_ at <time> must be in double quotes");
    }
    c.front().remove_prefix(1);
    c.back().remove_suffix(1);
    if (c.front().empty()) c.erase(c.begin());
    if (!c.empty() && c.back().empty()) c.pop_back();
    if (!c.empty() && c.front() == "$god_") return;
    const auto t = detail::parse_number(w[2]);
    if (!t) return skip(number, "time " + detail::quote(w[2]) + " is not a finite number");
    if (std::string why = detail::time_error(*t); !why.empty()) return skip(number, std::move(why));
    if (c.size() == 5 && c[1] == "setdest") return setdest(number, *t, c);
    if (c.size() == 4 && c[1] == "set") return timed_set(number, *t, c);
    skip(number, "expected \"$node_(i) setdest <x> <y> <speed>\" or \"$node_(i) set X_ <metres>\"");
  }

  void setdest(std::size_t number, double t, const std::vector<std::string_view>& c) {
    const auto node = node_of(number, c[0]);
    if (!node) return;
    const auto x = value_of(number, Axis::kX, c[2]);
    const auto y = x ? value_of(number, Axis::kY, c[3]) : std::nullopt;
    if (!y) return;
    const auto speed = detail::parse_number(c[4]);
    if (!speed || *speed < 0.0) {
      return skip(number, "speed " + detail::quote(c[4]) + " is not a number >= 0");
    }
    if (*speed > 0.0 && !std::isfinite(kLongestLegM / *speed)) {
      return skip(number, "speed " + format_coordinate(*speed) + " is too small for a leg to end");
    }
    Event e;
    e.t_s = t;
    e.setdest = true;
    e.x_m = *x;
    e.y_m = *y;
    e.speed_mps = *speed;
    scripts_[*node].events.push_back(e);
  }

  void timed_set(std::size_t number, double t, const std::vector<std::string_view>& c) {
    const auto node = node_of(number, c[0]);
    const auto axis = node ? axis_of(number, c[2]) : std::nullopt;
    if (!axis) return;
    const auto v = value_of(number, *axis, c[3]);
    if (!v) return;
    Event e;
    e.t_s = t;
    e.axis = *axis;
    e.value_m = *v;
    scripts_[*node].events.push_back(e);
  }

  std::optional<std::uint32_t> node_of(std::size_t number, std::string_view token) {
    std::optional<std::uint32_t> node;
    if (token.starts_with("$node_(") && token.ends_with(')')) {
      node = detail::parse_node(token.substr(7, token.size() - 8));
    }
    if (!node)
      skip(number, "node " + detail::quote(token) + " is not $node_(i) with i in 0..65535");
    return node;
  }

  std::optional<Axis> axis_of(std::size_t number, std::string_view token) {
    if (token == "X_") return Axis::kX;
    if (token == "Y_") return Axis::kY;
    if (token == "Z_") return Axis::kZ;
    skip(number, "unknown variable " + detail::quote(token) + ": expected X_, Y_ or Z_");
    return std::nullopt;
  }

  /// A coordinate along `axis`, checked against the same limits as a CSV sample.
  std::optional<double> value_of(std::size_t number, Axis axis, std::string_view token) {
    static constexpr const char* kNames[] = {"x", "y", "z"};
    const auto v = detail::parse_number(token);
    if (!v) {
      skip(number, std::string(kNames[static_cast<int>(axis)]) + " " + detail::quote(token) +
                       " is not a finite number");
      return std::nullopt;
    }
    LocalPosition p;
    coordinate(p, axis) = *v;
    if (std::string why = detail::sample_position_error(p); !why.empty()) {
      skip(number, std::move(why));
      return std::nullopt;
    }
    return v;
  }

  void skip(std::size_t number, std::string reason) {
    detail::skip_line(result_, number, std::move(reason));
  }

  /// ns-2's motion of one node as knots: a knot wherever its motion changes.
  static PiecewiseLinearTrack replay(NodeScript& script) {
    std::stable_sort(script.events.begin(), script.events.end(),
                     [](const Event& a, const Event& b) { return a.t_s < b.t_s; });
    std::vector<TrackKnot> knots{{0.0, script.initial}};
    LocalPosition at = script.initial;
    std::optional<TrackKnot> arrival;  // where and when the current leg ends
    for (const Event& e : script.events) {
      if (arrival && e.t_s >= arrival->time_s) {
        knots.push_back(*arrival);
        at = arrival->position;
        arrival.reset();
      } else if (arrival) {
        // Interrupted: the node is part way along the leg that left knots.back().
        const TrackKnot& from = knots.back();
        const double f = (e.t_s - from.time_s) / (arrival->time_s - from.time_s);
        at = {from.position.x_m + (arrival->position.x_m - from.position.x_m) * f,
              from.position.y_m + (arrival->position.y_m - from.position.y_m) * f, at.z_m};
        arrival.reset();
      }
      knots.push_back({e.t_s, at});  // the motion changes here
      if (!e.setdest) {
        coordinate(at, e.axis) = e.value_m;
        knots.push_back({e.t_s, at});  // a jump: two knots at one time
        continue;
      }
      const double length = std::hypot(e.x_m - at.x_m, e.y_m - at.y_m);
      if (e.speed_mps > 0.0 && length > 0.0) {
        arrival = TrackKnot{e.t_s + length / e.speed_mps, {e.x_m, e.y_m, at.z_m}};
      }
    }
    if (arrival) knots.push_back(*arrival);
    return PiecewiseLinearTrack(std::move(knots));
  }

  TraceParseResult& result_;
  std::map<std::uint32_t, NodeScript> scripts_;
};

}  // namespace

TraceParseResult parse_ns2_trace(std::string_view text, std::string source) {
  TraceParseResult result;
  result.source = std::move(source);
  Ns2Reader reader(result);
  detail::for_each_line(text, [&](std::size_t n, std::string_view line) { reader.line(n, line); });
  reader.finish();
  return result;
}

TraceParseResult read_ns2_trace(const std::string& path) {
  return parse_ns2_trace(detail::read_text_file(path), path);
}

}  // namespace rfsitl::position::mobility
