/// Mobility's share of a virtual-time run: how much of the engine's wall time
/// goes to moving the nodes (EngineStatus::mobility_wall_s: evaluating every
/// model and recomputing the moved nodes' links) in the load the
/// MAVLink/mobility issue names, with its target of below 5 %.
///
/// The load: N nodes on random waypoint in a box, the built-in gmsk PHY, and a
/// "ping" per node per virtual second. A ping is two scheduled frames (engine
/// traffic, not agents): an 80-byte frame to a random other node at a random
/// instant of the second, and that node's 8-byte answer 5 ms later. The answer
/// is scheduled whether or not the ping arrived (there is no agent to react),
/// so it measures the link back, not a round trip.
///
///   rfsitl_mobility_share [--nodes 64] [--update 0.01,0.001] [--duration 60,10]
///                         [--runs 3] [--csv FILE]
///
/// Prints, per mobility update interval, the median over --runs runs of the
/// wall and mobility seconds and the share, with the frame outcomes.
///
/// The i-th --duration goes with the i-th --update (one value: all of them).
/// Without --duration the first interval runs 60 s and the others 10 s: the
/// issue's figure is the 60 s run at the default 10 ms; the 1 ms run only
/// shows how the share scales, and is shorter to keep the whole
/// benchmark under two minutes on two cores: the load is the same every
/// second, so the share does not depend on the length (its first 10 s of
/// pings are the 60 s run's).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "rfsitl/common/percentile.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/engine/node_counter_fields.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/session/session.hpp"

namespace {

using namespace rfsitl;

constexpr std::size_t kPingBytes = 80;
constexpr std::size_t kAnswerBytes = 8;
constexpr double kAnswerDelayS = 0.005;
constexpr double kTargetSharePct = 5.0;
constexpr unsigned kIssueSeconds = 60;
constexpr unsigned kScalingSeconds = 10;

struct Options {
  std::size_t nodes = 64;
  std::vector<double> update_s{0.01, 0.001};
  std::vector<unsigned> seconds;  ///< per interval; empty: kIssueSeconds, then kScalingSeconds
  unsigned runs = 3;
  // Gmsk's sensitivity is 5.3 dB; with the paper channel's (d + 1)^-3 amplitude
  // and -120 dB noise that is a range of about 80 m. A 200 m box then keeps
  // roughly half the pairs in range at any moment, and mobility keeps
  // changing which half: both outcomes of a link happen all run long.
  double box_m = 200.0;
  double noise_db = -120.0;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  std::string csv;
};

/// What one run measured.
struct RunFigures {
  double virtual_s = 0.0;
  double wall_s = 0.0;
  double mobility_wall_s = 0.0;
  engine::NodeCountersSnapshot frames;  ///< summed over the nodes

  double share_pct() const { return wall_s > 0.0 ? 100.0 * mobility_wall_s / wall_s : NAN; }
};

scenario::MobilityChoice random_waypoint(const Options& o) {
  const auto* rwp = position::mobility::find_mobility("random_waypoint");
  scenario::MobilityChoice m{"random_waypoint", rwp->info.defaults()};
  const double half = o.box_m / 2.0;
  m.settings.set("x_min_m", -half);
  m.settings.set("x_max_m", half);
  m.settings.set("y_min_m", -half);
  m.settings.set("y_max_m", half);
  m.settings.set("z_min_m", 20.0);
  m.settings.set("z_max_m", 60.0);
  m.settings.set("speed_min_mps", 5.0);
  m.settings.set("speed_max_mps", 15.0);
  m.settings.set("pause_s", 1.0);
  // seed stays 0: every node's own stream, from the scenario seed and its id.
  return m;
}

/// The pings: the same schedule for every run and update interval (one seed,
/// drawn second by second, so a shorter run gets a prefix of a longer one's),
/// so the intervals differ only in how often the nodes move.
std::vector<scenario::TrafficItem> pings(const Options& o, unsigned seconds) {
  std::mt19937_64 rng(o.seed);
  // The answer must leave within the same second, and the last one before
  // the run ends.
  std::uniform_real_distribution<double> instant(0.0, 1.0 - kAnswerDelayS);
  std::uniform_int_distribution<std::size_t> peer(1, o.nodes - 1);
  std::vector<scenario::TrafficItem> items;
  for (unsigned k = 0; k < seconds; ++k) {
    for (std::size_t i = 0; i < o.nodes; ++i) {
      // An offset of 1..N-1 from the sender: any node but itself, uniformly.
      const std::size_t j = (i + peer(rng)) % o.nodes;
      const double at = k + instant(rng);
      const auto src = static_cast<NodeId>(i + 1);
      const auto dst = static_cast<NodeId>(j + 1);
      items.push_back({at, src, dst, kPingBytes, 1, 0.0});
      items.push_back({at + kAnswerDelayS, dst, src, kAnswerBytes, 1, 0.0});
    }
  }
  return items;
}

scenario::Scenario build(const Options& o, double update_s, unsigned seconds) {
  scenario::Scenario s;
  s.name = "mobility-share";
  s.seed = o.seed;
  s.timing.mode = scenario::TimeMode::kVirtual;
  // 50 ms past the last second, so that its last frames end on the air and
  // get their verdict (an 80-byte gmsk frame lasts under 2 ms at 1 Msps).
  s.timing.duration_s = seconds + 0.05;
  s.channel.noise_variance = std::pow(10.0, o.noise_db / 10.0);
  s.engine.threads = o.threads;
  s.engine.stats_interval_s = 0.0;
  s.engine.mobility_update_s = update_s;
  const scenario::MobilityChoice rwp = random_waypoint(o);
  for (std::size_t i = 0; i < o.nodes; ++i) {
    // No start position: the model draws one in its box.
    scenario::NodeConfig n = scenario::NodeConfig::at(static_cast<NodeId>(i + 1));
    n.mobility = rwp;
    s.nodes.push_back(std::move(n));
  }
  s.traffic = pings(o, seconds);
  scenario::validate_scenario(s);
  return s;
}

RunFigures run_once(const scenario::Scenario& s) {
  const session::SessionSummary summary = session::run_portless(s);
  const engine::EngineStatus& st = summary.status;
  RunFigures r{st.virtual_s, st.wall_s, st.mobility_wall_s, {}};
  for (const engine::NodeCountersSnapshot& c : summary.counters) {
    r.frames.handed_in += c.handed_in;
    r.frames.queue_dropped += c.queue_dropped;
    r.frames.delivered += c.delivered;
    for (std::size_t k = 0; k < engine::kNumLossReasons; ++k) r.frames.lost[k] += c.lost[k];
  }
  return r;
}

/// The median over the runs of one figure.
template <typename Get>
double median_of(const std::vector<RunFigures>& runs, Get get) {
  std::vector<double> v;
  for (const RunFigures& r : runs) v.push_back(static_cast<double>(get(r)));
  std::sort(v.begin(), v.end());
  return percentile(v, 0.5);
}

/// One row of medians. The frame counts are medians too, though with one seed
/// they should not vary between runs; run_interval() warns when they do.
struct Row {
  double update_s, virtual_s, wall_s, mobility_wall_s, share_pct;
  double handed_in, delivered, lost, queue_dropped;
  std::array<double, engine::kNumLossReasons> lost_by{};
};

Row medians(double update_s, const std::vector<RunFigures>& runs) {
  Row row{};
  row.update_s = update_s;
  row.virtual_s = median_of(runs, [](const RunFigures& r) { return r.virtual_s; });
  row.wall_s = median_of(runs, [](const RunFigures& r) { return r.wall_s; });
  row.mobility_wall_s = median_of(runs, [](const RunFigures& r) { return r.mobility_wall_s; });
  // The median of the shares, not the ratio of the medians: each share is one
  // run's own, under that run's load from other processes.
  row.share_pct = median_of(runs, [](const RunFigures& r) { return r.share_pct(); });
  row.handed_in = median_of(runs, [](const RunFigures& r) { return r.frames.handed_in; });
  row.delivered = median_of(runs, [](const RunFigures& r) { return r.frames.delivered; });
  row.lost = median_of(runs, [](const RunFigures& r) { return r.frames.lost_total(); });
  row.queue_dropped = median_of(runs, [](const RunFigures& r) { return r.frames.queue_dropped; });
  for (std::size_t k = 0; k < engine::kNumLossReasons; ++k) {
    row.lost_by[k] = median_of(runs, [k](const RunFigures& r) { return r.frames.lost[k]; });
  }
  return row;
}

Row run_interval(const Options& o, double update_s, unsigned seconds) {
  const scenario::Scenario s = build(o, update_s, seconds);
  std::vector<RunFigures> runs;
  for (unsigned k = 0; k < o.runs; ++k) {
    runs.push_back(run_once(s));
    const RunFigures& r = runs.back();
    // Progress on stderr: a run takes a while, and the spread shows the noise
    // other processes on the machine add.
    std::fprintf(stderr,
                 "mobility_share: update %g s run %u/%u: wall %.3f s mobility %.3f s (%.2f %%)\n",
                 update_s, k + 1, o.runs, r.wall_s, r.mobility_wall_s, r.share_pct());
  }
  const auto differs = [&](const RunFigures& r) {
    return r.frames.delivered != runs.front().frames.delivered ||
           r.frames.lost_total() != runs.front().frames.lost_total();
  };
  if (std::any_of(runs.begin(), runs.end(), differs)) {
    std::fprintf(stderr, "mobility_share: frame outcomes differ between runs of one seed\n");
  }
  return medians(update_s, runs);
}

void print_row(const Options& o, const Row& r) {
  std::printf(
      "mobility_share: update=%g ms nodes=%zu virtual=%.2f s wall=%.3f s mobility=%.3f s "
      "share=%.2f %% (target < %g %%: %s)\n"
      "  frames handed in %.0f delivered %.0f lost %.0f (",
      1e3 * r.update_s, o.nodes, r.virtual_s, r.wall_s, r.mobility_wall_s, r.share_pct,
      kTargetSharePct, r.share_pct < kTargetSharePct ? "met" : "not met", r.handed_in, r.delivered,
      r.lost);
  const char* sep = "";
  for (const engine::LossReasonInfo& info : engine::kLossReasons) {
    std::printf("%s%.*s %.0f", sep, static_cast<int>(info.key.size()), info.key.data(),
                r.lost_by[static_cast<std::size_t>(info.reason)]);
    sep = ", ";
  }
  std::printf(") queue-dropped %.0f\n", r.queue_dropped);
}

void append_csv(const Options& o, const std::vector<Row>& rows) {
  std::ifstream probe(o.csv);
  const bool fresh = !probe.good() || probe.peek() == std::ifstream::traits_type::eof();
  probe.close();
  std::ofstream out(o.csv, std::ios::app);
  if (fresh) {
    out << "nodes,update_s,runs,virtual_s,wall_s,mobility_wall_s,mobility_share_pct,handed_in,"
           "delivered,lost";
    for (const engine::LossReasonInfo& info : engine::kLossReasons) out << ",lost_" << info.key;
    out << ",queue_dropped\n";
  }
  for (const Row& r : rows) {
    out << o.nodes << "," << r.update_s << "," << o.runs << "," << r.virtual_s << "," << r.wall_s
        << "," << r.mobility_wall_s << "," << r.share_pct << "," << r.handed_in << ","
        << r.delivered << "," << r.lost;
    for (double n : r.lost_by) out << "," << n;
    out << "," << r.queue_dropped << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Mobility's share of the wall time of a virtual-time swarm run"};
  Options o;
  app.add_option("--nodes", o.nodes, "Nodes, all on random waypoint")
      ->check(CLI::Range(2, 250))
      ->capture_default_str();
  app.add_option("--duration", o.seconds, "Virtual seconds of pings, per interval or for all")
      ->delimiter(',')
      ->check(CLI::Range(1, 3600));
  app.add_option("--update", o.update_s, "Mobility update intervals to measure (s)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--runs", o.runs, "Runs per interval (the median is printed)")
      ->check(CLI::Range(1, 99))
      ->capture_default_str();
  app.add_option("--box", o.box_m, "Side of the square the nodes roam (m)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--noise-db", o.noise_db, "Channel noise power (dB)")->capture_default_str();
  app.add_option("--seed", o.seed, "Seed of noise, paths, ping times and peers")
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Worker threads (0: one per core)")->capture_default_str();
  app.add_option("--csv", o.csv, "Append one row per interval to this CSV (header if new)");
  CLI11_PARSE(app, argc, argv);
  if (o.seconds.empty()) {
    o.seconds.assign(o.update_s.size(), kScalingSeconds);
    o.seconds.front() = kIssueSeconds;
  } else if (o.seconds.size() == 1) {
    o.seconds.resize(o.update_s.size(), o.seconds.front());
  }
  if (o.seconds.size() != o.update_s.size()) {
    std::fprintf(stderr, "mobility_share: give one --duration, or one per --update interval\n");
    return 2;
  }

  std::printf(
      "mobility_share: %zu nodes on random_waypoint in %g x %g m, gmsk, noise %g dB; every node "
      "pings a random other node once a virtual second (%zu bytes), "
      "which answers %g ms later (%zu bytes), both as scheduled traffic, seed %llu; median of %u "
      "runs\n",
      o.nodes, o.box_m, o.box_m, o.noise_db, kPingBytes, 1e3 * kAnswerDelayS, kAnswerBytes,
      static_cast<unsigned long long>(o.seed), o.runs);
  std::fflush(stdout);
  std::vector<Row> rows;
  try {
    for (std::size_t i = 0; i < o.update_s.size(); ++i) {
      rows.push_back(run_interval(o, o.update_s[i], o.seconds[i]));
      print_row(o, rows.back());
      std::fflush(stdout);
    }
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "mobility_share: %s\n", ex.what());
    return 2;
  }
  if (!o.csv.empty()) append_csv(o, rows);
  return 0;
}
