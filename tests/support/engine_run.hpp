#pragma once
/// Runs an engine over a scenario in virtual time and collects what came out:
/// the frames handed to the sink (with the tick they came in), every node's
/// counters and the engine's status.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::testing {

struct Delivery {
  std::size_t node = 0;
  NetFrame frame;
  SampleTime tick_start = 0;  ///< virtual time of the tick in which it was delivered
  friend bool operator==(const Delivery&, const Delivery&) = default;
};

/// Records deliveries; engine thread only.
class RecordingSink final : public engine::FrameSink {
 public:
  void deliver(std::size_t node, NetFrame&& frame) override;

  engine::Engine* engine = nullptr;
  std::vector<Delivery> deliveries;
  /// Called after recording each delivery (e.g. to answer it with submit()).
  std::function<void(engine::Engine&, const Delivery&)> on_deliver;
};

/// (Every member has an initializer so that designated initializers may name
/// only what they set: GCC warns of missing ones otherwise.)
struct RunSetup {
  /// Empty: the real transceivers of the PHY registry.
  engine::TransceiverFactory factory = {};
  /// Added before the run; must outlive the RunResult.
  std::vector<engine::EngineObserver*> observers = {};
  /// Called once the engine is built, before run() (e.g. to submit frames).
  std::function<void(engine::Engine&)> before = {};
  std::function<void(engine::Engine&, const Delivery&)> on_deliver = {};
};

struct RunResult {
  std::vector<Delivery> deliveries;
  std::vector<engine::NodeCountersSnapshot> counters;
  engine::EngineStatus status;
  /// The engine after its run, kept alive (with its transceivers) for inspection.
  std::shared_ptr<RecordingSink> sink;
  std::shared_ptr<engine::Engine> engine;

  std::uint64_t lost(std::size_t node, engine::LossReason r) const {
    return counters[node].lost[static_cast<std::size_t>(r)];
  }
};

/// Runs `s` until its duration has been emulated.
RunResult run_engine(const scenario::Scenario& s, RunSetup setup = {});

using NodeSpec = std::pair<NodeId, std::optional<LocalPosition>>;

/// Virtual time, fs = 1 MHz, ticks of 1000 samples, noise at -120 dB, two
/// workers, the default PHY; nodes at local positions (nullopt: unknown).
scenario::Scenario make_scenario(const std::vector<NodeSpec>& nodes, double duration_s);

/// One scenario frame of `size` bytes from `src` to `dst` at `at_s` seconds.
scenario::TrafficItem frame_at(double at_s, NodeId src, NodeId dst, std::size_t size = 80);

/// Five frames of `bytes` among nodes 1, 2 and 3 (one a broadcast), 6 ms
/// apart from 2 ms on: none overlap another while a frame lasts under 6 ms.
std::vector<scenario::TrafficItem> collision_free_traffic(std::size_t bytes);

/// Expects the same deliveries and the same counters (except the I/O ones).
void expect_same_outcome(const RunResult& a, const RunResult& b);

}  // namespace rfsitl::testing
