#pragma once
// Internal to the scenario module: the limits every setting must respect and the
// Context that makes errors point at "<source>:<line>: <dotted.key>". Shared by
// the YAML reader (scenario_loader.cpp) and validate() (scenario_validation.cpp).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::scenario::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

inline std::string fmt(double v) {
  std::array<char, 32> buf{};
  return {buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr};
}

inline ScenarioError make_error(const std::string& source, int line, std::string_view key,
                                std::string_view reason) {
  std::string msg = line > 0 ? source + ":" + std::to_string(line) : source;
  msg.append(": ").append(key).append(": ").append(reason);
  return ScenarioError(msg);
}

// ---- limits ------------------------------------------------------------------------------

struct IntLimit {  // every integer setting is unsigned
  std::uint64_t lo;
  std::uint64_t hi;
  bool contains(std::uint64_t v) const { return v >= lo && v <= hi; }
  std::string describe() const {
    return "must be in " + std::to_string(lo) + ".." + std::to_string(hi);
  }
};

struct RealLimit {  // NaN and infinities are never in range
  double lo;
  double hi;
  bool lo_open = false;
  bool hi_open = false;
  bool contains(double v) const {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string describe() const {
    if (lo == -kInf && hi == kInf) return "must be a finite number";
    if (hi == kInf) return std::string("must be ") + (lo_open ? "> " : ">= ") + fmt(lo);
    return std::string("must be in ") + (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) +
           (hi_open ? ")" : "]");
  }
};

constexpr IntLimit kNodeIdLimit{kMinNodeId, kMaxNodeId};
constexpr IntLimit kDstLimit{kMinNodeId, kBroadcastId};  // listed or broadcast: validate()
constexpr IntLimit kTickSamples{1, 1U << 20};
constexpr IntLimit kTxQueue{1, 65536};
constexpr IntLimit kAnyInteger{0, std::numeric_limits<std::uint64_t>::max()};
constexpr IntLimit kSize{1, 65535};  // traffic sizes; validate(): <= the PHY's max payload
constexpr IntLimit kThreads{0, 256};
constexpr IntLimit kPort{0, 65535};
constexpr IntLimit kSeed{0, std::numeric_limits<std::uint64_t>::max()};
constexpr IntLimit kRepeat{1, std::numeric_limits<unsigned>::max()};
constexpr RealLimit kPositive{0, kInf, true};
constexpr RealLimit kNonNegative{0, kInf};
constexpr RealLimit kFinite{-kInf, kInf};
constexpr RealLimit kNoisePowerDb{-300, 300};  // keeps 10^(dB/10) a normal, non-zero double
// Seconds; the hub waits in int milliseconds, which 1e30 s would overflow (undefined).
constexpr RealLimit kReplyTimeout{0, 3600, true};

constexpr std::array<std::string_view, 2> kTimeModes{"realtime", "virtual"};
constexpr std::array<std::string_view, 1> kChannelModels{"paper"};
constexpr std::array<std::string_view, 2> kProcesses{"inline", "child"};
// One tick's samples must fit one socket message for external transceivers.
constexpr IntLimit kExternalTickSamples{1, 16384};

template <typename Names>
std::string join(const Names& names) {
  std::string out;
  for (const auto& n : names) out.append(out.empty() ? "" : ", ").append(n);
  return out;
}

template <typename Names>
bool is_one_of(std::string_view v, const Names& names) {
  return std::find(names.begin(), names.end(), v) != names.end();
}

// ---- context: where errors point --------------------------------------------------------

// The source name and the line of every key read from it. A key without a line of its
// own takes its nearest parent's ("nodes[2].position.lat" -> "nodes[2].position" ->
// "nodes[2]" -> "nodes"); with no line at all the message reads "<source>: <key>: ...".
class Context {
 public:
  explicit Context(std::string source) : source_(std::move(source)) {}

  void record(const std::string& key, int line) { lines_[key] = line; }
  int line(std::string key) const {
    for (;;) {
      if (const auto it = lines_.find(key); it != lines_.end()) return it->second;
      if (key.empty()) return 0;
      const auto cut = key.find_last_of(".[");
      key.resize(cut == std::string::npos ? 0 : cut);  // "" is the whole document
    }
  }
  /// "<source>:<line>" of `key` (or of the closest enclosing key that has a
  /// line), or "<source>" when none has: a flag's name, "scenario".
  std::string where(const std::string& key) const {
    const int l = line(key);
    return l > 0 ? source_ + ":" + std::to_string(l) : source_;
  }
  [[noreturn]] void fail(const std::string& key, std::string_view reason) const {
    throw make_error(source_, line(key), key, reason);
  }
  void check(std::uint64_t v, const std::string& key, IntLimit lim) const {
    if (!lim.contains(v)) fail(key, lim.describe() + ", got " + std::to_string(v));
  }
  void check(double v, const std::string& key, RealLimit lim) const {
    if (!lim.contains(v)) fail(key, lim.describe() + ", got " + fmt(v));
  }
  // Positions take the limits every input shares (rfsitl/common/position_limits.hpp)
  // as they are, so that no copy here can drift from them.
  void check(double v, const std::string& key, CoordinateLimit lim) const {
    check(v, key, RealLimit{lim.lo, lim.hi});
  }
  template <typename Names>
  void check_name(const std::string& v, const std::string& key, const Names& names) const {
    if (!is_one_of(v, names)) fail(key, "unknown '" + v + "' (known: " + join(names) + ")");
  }

 private:
  std::string source_;
  std::map<std::string, int, std::less<>> lines_;
};

/// Checks every range and cross-field rule of `s`; errors name lines through `c`.
void validate(const Scenario& s, const Context& c);

}  // namespace rfsitl::scenario::detail
