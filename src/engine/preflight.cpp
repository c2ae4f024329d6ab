#include "rfsitl/engine/preflight.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <random>
#include <thread>

#include "rfsitl/engine/engine.hpp"

namespace rfsitl::engine {
namespace {

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto s = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return s(u.ru_utime) + s(u.ru_stime);
}

/// Frames go nowhere: only the engine's cost is measured.
class DiscardSink final : public FrameSink {
 public:
  void deliver(std::size_t, NetFrame&&) override {}
};

/// The capacity benchmark's load: node i pings a random other node once a
/// second from i / N s on, and is answered 5 ms later (seeded: the same every time).
std::vector<scenario::TrafficItem> ping_load(const scenario::Scenario& s, double seconds) {
  std::vector<scenario::TrafficItem> out;
  const std::size_t n = s.nodes.size();
  if (n < 2) return out;
  std::mt19937_64 pick(s.seed);
  const auto repeat = static_cast<unsigned>(std::ceil(seconds)) + 1;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t j = std::uniform_int_distribution<std::size_t>(0, n - 2)(pick);
    if (j >= i) ++j;
    const double at = static_cast<double>(i) / static_cast<double>(n);
    out.push_back({at, s.nodes[i].id, s.nodes[j].id, 64, repeat, 1.0});
    out.push_back({at + 0.005, s.nodes[j].id, s.nodes[i].id, 64, repeat, 1.0});
  }
  return out;
}

}  // namespace

std::string PreflightReport::summary() const {
  char line[320];
  const char* load = own_traffic ? "the scenario's traffic"
                                 : "a stand-in load: every node pings another once a second";
  if (speed() < 1.0) {
    std::snprintf(line, sizeof line,
                  "real time will not hold: this machine emulates %.2f s per second (needs %.1f "
                  "cores of %zu) under %s; try fewer nodes, --speed %.2f, or virtual time",
                  speed(), cores_needed(), cores, load, std::max(0.01, 0.9 * speed()));
  } else {
    std::snprintf(line, sizeof line,
                  "real time %s: needs %.2f cores of %zu (speed %.1fx, %.0f %% margin) under %s",
                  margin() >= kPreflightMinMargin ? "holds" : "holds with little margin",
                  cores_needed(), cores, speed(), 100.0 * margin(), load);
  }
  return line;
}

PreflightReport preflight(const scenario::Scenario& s, double seconds, double max_wall_s) {
  scenario::Scenario v = s;
  v.timing.mode = scenario::TimeMode::kVirtual;
  if (s.timing.duration_s > 0.0) seconds = std::min(seconds, s.timing.duration_s);
  v.timing.duration_s = seconds;
  if (v.phy.runs_externally()) v.phy = scenario::PhyChoice{};
  for (scenario::NodeConfig& node : v.nodes) {
    if (node.phy && node.phy->runs_externally()) node.phy.reset();
  }
  PreflightReport r;
  r.own_traffic = !v.traffic.empty();
  if (!r.own_traffic) v.traffic = ping_load(v, seconds);
  r.cores = std::max(1U, std::thread::hardware_concurrency());
  DiscardSink sink;
  const std::unique_ptr<Engine> e = make_engine(v, sink);
  std::atomic<bool> stop{false};
  std::mutex m;
  std::condition_variable done;
  bool finished = false;
  const double cpu0 = process_cpu_s();
  const auto t0 = std::chrono::steady_clock::now();
  // Stops a run that takes longer than max_wall_s; ends at once when it is over.
  std::thread watchdog([&] {
    std::unique_lock lock(m);
    if (!done.wait_for(lock, std::chrono::duration<double>(max_wall_s), [&] { return finished; }))
      stop = true;
  });
  e->run(stop);
  {
    const std::lock_guard lock(m);
    finished = true;
  }
  done.notify_one();
  watchdog.join();
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_s = process_cpu_s() - cpu0;
  r.virtual_s = e->status().virtual_s;
  for (std::size_t i = 0; i < e->num_nodes(); ++i) r.frames += e->counters(i).snapshot().handed_in;
  return r;
}

}  // namespace rfsitl::engine
