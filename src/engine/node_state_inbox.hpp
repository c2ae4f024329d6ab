#pragma once
// Internal to the engine: where positions and motion from other threads (the
// location ports, the dashboard, live position sources) wait for the engine
// thread, and where each node's velocity and attitude are kept for readers.
// In a distributed run the updates a rank takes are applied by every rank
// (tick_exchange.hpp), so they travel as StateUpdates.
#include <atomic>
#include <cstddef>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/position/source/node_state.hpp"
#include "rfsitl/position/source/velocity_estimator.hpp"
#include "tick_exchange.hpp"

namespace rfsitl::engine {

class NodeStateInbox {
 public:
  NodeStateInbox(std::size_t nodes, GeodeticPosition origin);

  /// Any thread: node `node` moves at the next apply() of take(). `with_velocity`:
  /// its source reports the velocity itself (set with set_motion), so none is
  /// estimated from the positions.
  void move(std::size_t node, std::optional<Ecef> position, bool with_velocity);

  /// Any thread: the parts of `motion` that are set replace the node's at the
  /// next apply() of take().
  void set_motion(std::size_t node, const position::NodeMotion& motion);

  /// Engine thread: as set_motion, at once (a mobility model, which every rank
  /// of a distributed run evaluates itself).
  void set_motion_now(std::size_t node, const position::NodeMotion& motion);

  /// Engine thread: the updates waiting, in node order, and none left waiting.
  std::vector<StateUpdate> take();

  /// Engine thread: applies `updates` in order to `channel` at virtual time
  /// `now_s`, estimating the velocity of positions that came without one.
  /// True when any node moved.
  bool apply(std::span<const StateUpdate> updates, double now_s, channel::ChannelMatrix& channel);

  /// Engine thread: whether any motion changed since the last call.
  bool motion_changed() { return motion_dirty_.exchange(false, std::memory_order_acq_rel); }

  /// Any thread: every node's velocity and attitude.
  std::vector<position::NodeMotion> motions() const;

 private:
  GeodeticPosition origin_;
  std::mutex pending_mutex_;
  std::vector<std::optional<StateUpdate>> pending_;
  std::atomic<bool> dirty_{false};
  std::atomic<bool> motion_dirty_{false};
  std::vector<position::VelocityEstimator> estimators_;  // engine thread only
  mutable std::mutex motions_mutex_;
  std::vector<position::NodeMotion> motions_;
};

}  // namespace rfsitl::engine
