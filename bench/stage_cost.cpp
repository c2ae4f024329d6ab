/// What each channel stage costs, measured on the channel alone (no
/// transceivers), one thread:
///
///   rfsitl_stage_cost [--nodes N] [--active K] [--ticks T] [--csv FILE]
///
/// For every stage and model of the README's table, a scenario with that stage
/// after free-space path loss (the paper's model alone for `paper`), N nodes in
/// the default formation, each moving at 10 m/s (so that fading has a Doppler),
/// 2.4 GHz, 1 Msps, 250-sample ticks:
///   - per sample: K transmitters on the air, every other node receives T ticks;
///     the time above the same receivers with no transmitter (their noise and
///     front end) divided by links x samples: ns per link and sample;
///   - per move: set_position of every node in turn (each recomputes its
///     2 (N - 1) links): ns per link recomputed.
/// Medians of five timed runs.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rfsitl/channel/channel.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/scenario/link_budget_of.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace {

using namespace rfsitl;
using Clock = std::chrono::steady_clock;

struct Case {
  const char* stage;
  const char* model;
  const char* yaml;  // channel.stages after free-space path loss; "" for none
  bool paper = false;
};

// One line of YAML per stage, as a user would write it (defaults otherwise).
const Case kCases[] = {
    {"path_loss", "paper", "", true},
    {"path_loss", "free_space", ""},
    {"path_loss", "log_distance",
     "    - {type: path_loss, model: log_distance, exponent: 3, reference_distance_m: 10}\n"},
    {"path_loss", "two_ray", "    - {type: path_loss, model: two_ray}\n"},
    {"path_loss", "tr36777_uma_av", "    - {type: path_loss, model: tr36777_uma_av}\n"},
    {"shadowing", "", "    - {type: shadowing, sigma_db: 4, decorrelation_m: 20}\n"},
    {"antenna", "dipole", "    - {type: antenna, pattern: dipole}\n"},
    {"antenna", "patch", "    - {type: antenna, pattern: patch}\n"},
    {"occlusion", "",
     "    - {type: occlusion, sectors: [{azimuth_deg: 180, elevation_deg: 0, half_angle_deg: 30, "
     "loss_db: 10}]}\n"},
    {"fading", "rayleigh", "    - {type: fading, model: rayleigh}\n"},
    {"fading", "rician", "    - {type: fading, model: rician, k_db: 6}\n"},
    {"delay", "", "    - {type: delay}\n"},
    {"multipath", "tdl_c", "    - {type: multipath, profile: tdl_c, delay_spread_ns: 100}\n"},
    {"multipath", "taps (4)",
     "    - {type: multipath, profile: taps, taps: [{delay_ns: 0, gain_db: 0}, {delay_ns: 100, "
     "gain_db: -3}, {delay_ns: 200, gain_db: -6}, {delay_ns: 300, gain_db: -9}]}\n"},
    // The file is written by trace_file() for the run's node count.
    {"trace", "csv, 11 points per link", "    - {type: trace, file: TRACE_FILE, loop: true}\n"},
    {"delay + multipath + fading", "taps (4), rician",
     "    - {type: delay}\n    - {type: multipath, profile: taps, taps: [{delay_ns: 0, gain_db: "
     "0}, {delay_ns: 100, gain_db: -3}, {delay_ns: 200, gain_db: -6}, {delay_ns: 300, gain_db: "
     "-9}]}\n    - {type: fading, model: rician, k_db: 6}\n"},
};

/// A CSV trace for nodes 1..n (the default formation's ids): every pair's
/// gain and phase at 11 points over one second (the stage loops it and
/// applies each row to both directions), in the system's temporary folder.
std::string trace_file(std::size_t nodes) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("rfsitl_stage_cost_trace_" + std::to_string(nodes) + ".csv");
  std::ofstream out(path);
  out << "t_s,tx,rx,gain_db,phase_deg\n";
  for (std::size_t a = 1; a <= nodes; ++a) {
    for (std::size_t b = a + 1; b <= nodes; ++b) {
      for (int k = 0; k <= 10; ++k) {
        out << 0.1 * k << ',' << a << ',' << b << ','
            << -60.0 - static_cast<double>((a + b + k) % 10) << ','
            << static_cast<double>((37 * (a + k) + b) % 360) << '\n';
      }
    }
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return path.string();
}

scenario::Scenario scenario_of(const Case& c, std::size_t nodes) {
  std::string yaml = "name: stage-cost\n";
  if (!c.paper) {
    yaml += "radio: {carrier_hz: 2.4e9, tx_power_dbm: 20, noise_figure_db: 7}\n";
    yaml += "channel:\n  stages:\n";
    // The antenna and occlusion stages need no attitude: without one a node
    // points north, level.
    if (std::string(c.stage) != "path_loss" || std::string(c.model) == "free_space") {
      yaml += "    - {type: path_loss, model: free_space}\n";
    }
    std::string stages = c.yaml;
    if (const auto at = stages.find("TRACE_FILE"); at != std::string::npos) {
      stages.replace(at, 10, trace_file(nodes));
    }
    yaml += stages;
  }
  yaml += "nodes: " + std::to_string(nodes) + "\n";
  return scenario::parse_scenario(yaml, "stage_cost");
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Cost {
  double ns_per_link_sample = 0.0;
  double ns_per_link_update = 0.0;
};

Cost measure(const scenario::Scenario& s, std::size_t active, std::size_t ticks, float* sink) {
  const std::size_t n = s.nodes.size();
  const std::size_t b = s.timing.tick_samples;
  channel::Channel ch(
      n, scenario::make_link_budget(s), s.channel.origin,
      channel::ChannelConfig{s.channel.noise_variance, false, s.seed, s.timing.sample_rate_hz, b});
  std::vector<Ecef> at(n);
  for (std::size_t i = 0; i < n; ++i) {
    at[i] = to_ecef(*s.nodes[i].initial_position, s.channel.origin);
    ch.matrix().set_position(i, at[i]);
    // Each node flies east or north at 10 m/s: every link has a Doppler.
    ch.matrix().set_velocity(i, i % 2 == 0 ? channel::LocalVelocity{10.0, 0.0, 0.0}
                                           : channel::LocalVelocity{0.0, 10.0, 0.0});
  }
  std::vector<std::vector<cf32>> x(active, std::vector<cf32>(b));
  std::vector<channel::Transmission> on_air;
  for (std::size_t k = 0; k < active; ++k) {
    for (std::size_t t = 0; t < b; ++t) {
      x[k][t] = {(t + k) % 3 == 0 ? 1.0F : -1.0F, (t * 7 + k) % 5 < 2 ? 1.0F : -1.0F};
    }
    on_air.push_back({k, x[k].data()});
  }
  std::vector<cf32> y(b);
  channel::Channel::Scratch scratch;
  // Receivers: every node not on the air. The same ticks with and without
  // transmitters; the difference is what the links cost.
  const auto run = [&](std::span<const channel::Transmission> txs, std::uint64_t first_tick) {
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < ticks; ++k) {
      const auto start = static_cast<SampleTime>((first_tick + k) * b);
      ch.matrix().set_clock(static_cast<double>(start) / s.timing.sample_rate_hz);
      ch.on_air(start, txs);
      ch.begin_tick(start, true);
      for (std::size_t m = active; m < n; ++m) {
        ch.receive(m, 0, y, scratch);
        *sink += y[k % b].real();
      }
    }
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
  };
  const double links = static_cast<double>(active * (n - active));
  std::vector<double> per_sample;
  std::uint64_t tick = 0;
  run(on_air, tick);  // warm up: caches, the fading stage's kept draws
  tick += ticks;
  for (int r = 0; r < 5; ++r) {
    const double with = run(on_air, tick);
    tick += ticks;
    const double without = run({}, tick);
    tick += ticks;
    per_sample.push_back((with - without) / (links * static_cast<double>(ticks * b)));
  }
  std::vector<double> per_update;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      at[i].x += 0.5;  // a small move: every link of node i is recomputed
      ch.matrix().set_position(i, at[i]);
    }
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
    per_update.push_back(ns / static_cast<double>(n * 2 * (n - 1)));
  }
  *sink += ch.matrix().power_gain(0, 1);
  return {median(per_sample), median(per_update)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The cost of each channel stage: ns per link and sample, ns per link update"};
  std::size_t nodes = 16;
  std::size_t active = 4;
  std::size_t ticks = 400;
  std::string csv = "stage_cost.csv";
  app.add_option("--nodes", nodes, "Nodes (default formation)")
      ->check(CLI::Range(2, 254))
      ->capture_default_str();
  app.add_option("--active", active, "Transmitters on the air")
      ->check(CLI::Range(1, 253))
      ->capture_default_str();
  app.add_option("--ticks", ticks, "250-sample ticks per timed run")
      ->check(CLI::Range(10, 1000000))
      ->capture_default_str();
  app.add_option("--csv", csv, "Output CSV")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (active >= nodes) {
    std::fprintf(stderr, "rfsitl_stage_cost: --active must be below --nodes\n");
    return 2;
  }

  float sink = 0.0F;
  std::ofstream out(csv);
  try {
    out << "stage,model,ns_per_link_sample,ns_per_link_update\n";
    std::printf("%-28s %-18s %14s %14s\n", "stage", "model", "ns/link/sample", "ns/link update");
    for (const Case& c : kCases) {
      const Cost cost = measure(scenario_of(c, nodes), active, ticks, &sink);
      std::printf("%-28s %-18s %14.2f %14.1f\n", c.stage, c.model, cost.ns_per_link_sample,
                  cost.ns_per_link_update);
      out << '"' << c.stage << "\",\"" << c.model << "\"," << cost.ns_per_link_sample << ","
          << cost.ns_per_link_update << "\n";
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl_stage_cost: %s\n", e.what());
    return 1;
  }
  std::printf(
      "stage_cost: %zu nodes, %zu on the air, %zu ticks of 250 samples at 1 Msps; wrote %s "
      "(checksum %g)\n",
      nodes, active, ticks, csv.c_str(), static_cast<double>(sink));
  return 0;
}
