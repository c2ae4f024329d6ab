/// Virtual-time speed: simulated seconds per wall-clock second of a run in
/// virtual time (in process: a session assembled as `rfsitl run --mode virtual`
/// assembles it, without ports), N nodes in the default formation, every node
/// sending one frame per second to a random other node, at a uniformly random
/// time within each second (scheduled traffic, no acks; the same load as
/// rfsitl_swarm_load's pings).
///
///   rfsitl_virtual_speed [--nodes 15] [--duration 60] [--csv FILE] [--no-skip]
///                        [--fading rayleigh|rician] [--multipath tdl_a|tdl_b|tdl_c|taps4]
///   rfsitl_virtual_speed --scenario FILE   (that file's run instead, in virtual time)
///
/// --fading adds that fading stage (its defaults: M = 32, a 10 kHz grid) after
/// the paper's path loss, so the two speeds compare a flat and a faded channel.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <string>

#include "rfsitl/config/record.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/session/session.hpp"

namespace {

using namespace rfsitl;

struct Options {
  std::size_t nodes = 15;
  double duration_s = 60.0;
  double rate_hz = 1.0;
  std::size_t size = 80;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  bool no_skip = false;
  std::string fading;     // "": the flat channel
  std::string multipath;  // "": no delay or multipath stages
  std::string csv;
  std::string scenario;  // "": the default formation built below
};

scenario::Scenario build(const Options& o) {
  scenario::Scenario s;
  s.name = "virtual-speed";
  s.seed = o.seed;
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.engine.threads = o.threads;
  s.engine.skip_idle_receivers = !o.no_skip;
  s.engine.stats_interval_s = 0.0;
  s.nodes = scenario::default_formation(o.nodes, s.channel);
  if (!o.fading.empty() || !o.multipath.empty()) {
    const auto stage = [](const char* type) {
      return scenario::StageChoice{type, channel::find_channel_stage(type)->info.defaults()};
    };
    scenario::StageChoice paper = stage("path_loss");
    paper.settings.set("paper_exponent", s.channel.path_loss_exponent);
    s.channel.stages = {paper};
    if (!o.multipath.empty()) {
      // Propagation delay, then the profile's taps (100 ns of delay spread).
      s.channel.stages.push_back(stage("delay"));
      scenario::StageChoice taps = stage("multipath");
      if (o.multipath == "taps4") {
        // Four taps 100 ns apart falling 3 dB each (as Colosseum's four
        // non-zero taps per link).
        config::Records four;
        for (int i = 0; i < 4; ++i) {
          config::Record r;
          r.set("delay_ns", 100.0 * i);
          r.set("gain_db", -3.0 * i);
          four.push_back(r);
        }
        taps.settings.set("profile", std::string("taps"));
        taps.settings.set("taps", four);
      } else {
        taps.settings.set("profile", o.multipath);
      }
      s.channel.stages.push_back(taps);
    }
    if (!o.fading.empty()) {
      scenario::StageChoice faded = stage("fading");
      faded.settings.set("model", o.fading);
      s.channel.stages.push_back(faded);
    }
  }
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> within(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> other(0, o.nodes - 2);
  const auto per_node = static_cast<unsigned>(o.duration_s * o.rate_hz);
  for (std::size_t i = 0; i < o.nodes; ++i) {
    for (unsigned k = 0; k < per_node; ++k) {
      std::size_t j = other(rng);
      if (j >= i) ++j;
      const double at = (k + within(rng)) / o.rate_hz;
      s.traffic.push_back({at, s.nodes[i].id, s.nodes[j].id, o.size, 1, 0.0});
    }
  }
  // The last frames (sent up to duration_s) get time to end on the air.
  s.timing.duration_s = o.duration_s + 0.05;
  scenario::validate_scenario(s);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Virtual-time speed: simulated seconds per wall second"};
  Options o;
  app.add_option("--nodes", o.nodes, "Nodes in the default formation")
      ->check(CLI::Range(2, 250))
      ->capture_default_str();
  app.add_option("--duration", o.duration_s, "Simulated seconds of traffic")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--rate", o.rate_hz, "Frames per node per simulated second")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--size", o.size, "Payload bytes per frame")->capture_default_str();
  app.add_option("--seed", o.seed, "Seed of noise, send times and destinations")
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Worker threads (0: one per core)")->capture_default_str();
  app.add_flag("--no-skip", o.no_skip, "Run every receiver every tick");
  app.add_option("--fading", o.fading, "Add a fading stage of this model (rayleigh, rician)");
  app.add_option("--multipath", o.multipath,
                 "Add the delay stage and a multipath stage of this profile (tdl_a, tdl_b, "
                 "tdl_c, or taps4: four taps 100 ns apart, 3 dB apart)");
  app.add_option("--csv", o.csv, "Append one result row to this CSV (header if new)");
  app.add_option("--scenario", o.scenario,
                 "Run this scenario file (in virtual time) instead of the default formation; "
                 "the options that build one are then ignored, --threads and --no-skip apply");
  CLI11_PARSE(app, argc, argv);

  // Assembled as `rfsitl run --mode virtual` assembles a run (the session),
  // without ports: decoded frames are dropped, and counted.
  session::SessionOptions options;
  options.ports = false;
  std::unique_ptr<session::Session> run;
  try {
    if (o.scenario.empty()) {
      options.scenario = build(o);
    } else {
      options.scenario_path = o.scenario;
      options.settings = {{"time.mode", "virtual", "--scenario"},
                          {"engine.threads", std::to_string(o.threads), "--threads"}};
      if (o.no_skip)
        options.settings.push_back({"engine.skip_idle_receivers", "false", "--no-skip"});
    }
    run = std::make_unique<session::Session>(std::move(options));
    run->assemble();
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "virtual_speed: %s\n", ex.what());
    return 2;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const session::ServeResult served = run->serve();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (served.end != session::ServeEnd::kCompleted) {
    std::fprintf(stderr, "virtual_speed: the run failed: %s\n", served.error.c_str());
    return 1;
  }
  const session::SessionSummary& summary = run->finish();
  const engine::EngineStatus& st = summary.status;

  engine::NodeCountersSnapshot total;
  for (const auto& c : summary.counters) {
    total.handed_in += c.handed_in;
    total.delivered += c.delivered;
    total.queue_dropped += c.queue_dropped;
    for (std::size_t r = 0; r < engine::kNumLossReasons; ++r) total.lost[r] += c.lost[r];
  }
  const double speed = st.virtual_s / wall;
  const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
  std::printf(
      "virtual_speed: nodes=%zu skip=%s fading=%s multipath=%s virtual=%.3f s wall=%.3f s "
      "speed=%.2f x real "
      "time; "
      "frames %llu delivered %llu lost %llu (collision %llu, half-duplex %llu) "
      "receiver-ticks run %llu skipped %llu; workers at the end %zu\n",
      summary.node_ids.size(), o.no_skip ? "off" : "on",
      o.fading.empty() ? "none" : o.fading.c_str(),
      o.multipath.empty() ? "none" : o.multipath.c_str(), st.virtual_s, wall, speed,
      u(total.handed_in), u(total.delivered), u(total.lost_total()),
      u(total.lost[static_cast<std::size_t>(engine::LossReason::kCollision)]),
      u(total.lost[static_cast<std::size_t>(engine::LossReason::kHalfDuplex)]),
      u(st.receiver_ticks_run), u(st.receiver_ticks_skipped), st.workers);
  if (!o.csv.empty()) {
    std::ifstream probe(o.csv);
    const bool fresh = !probe.good() || probe.peek() == std::ifstream::traits_type::eof();
    probe.close();
    std::ofstream out(o.csv, std::ios::app);
    if (fresh) {
      out << "nodes,skip_idle,fading,multipath,rate_hz,virtual_s,wall_s,speed_x,frames,delivered,"
             "lost,queue_dropped,receiver_ticks_run,receiver_ticks_skipped\n";
    }
    out << summary.node_ids.size() << "," << (o.no_skip ? 0 : 1) << ","
        << (o.fading.empty() ? "none" : o.fading) << ","
        << (o.multipath.empty() ? "none" : o.multipath) << "," << o.rate_hz << "," << st.virtual_s
        << "," << wall << "," << speed << "," << total.handed_in << "," << total.delivered << ","
        << total.lost_total() << "," << total.queue_dropped << "," << st.receiver_ticks_run << ","
        << st.receiver_ticks_skipped << "\n";
  }
  return 0;
}
