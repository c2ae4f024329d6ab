#pragma once
// The smallest scenario the monitor tests run an engine on, and a sink that
// drops what the engine delivers (these tests read counters, not frames).
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor::test {

class NullSink final : public engine::FrameSink {
 public:
  void deliver(std::size_t, NetFrame&&) override {}
};

/// Nodes 1 and 2, 10 m apart at 10 m height, virtual time, no traffic.
inline scenario::Scenario two_nodes(double duration_s = 0.01) {
  scenario::Scenario s;
  s.name = "dashboard-test";
  for (NodeId id = 1; id <= 2; ++id) {
    scenario::NodeConfig n;
    n.id = id;
    n.initial_position = LocalPosition{10.0 * (id - 1), 0, 10};
    s.nodes.push_back(n);
  }
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.duration_s = duration_s;
  return s;
}

}  // namespace rfsitl::monitor::test
