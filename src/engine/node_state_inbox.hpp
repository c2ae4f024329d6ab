#pragma once
// Internal to the engine: where positions and motion from other threads (the
// location ports, the dashboard, live position sources) wait for the engine
// thread, and where each node's velocity and attitude are kept for readers.
#include <atomic>
#include <cstddef>
#include <mutex>
#include <optional>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/position/source/node_state.hpp"
#include "rfsitl/position/source/velocity_estimator.hpp"

namespace rfsitl::engine {

class NodeStateInbox {
 public:
  NodeStateInbox(std::size_t nodes, GeodeticPosition origin);

  /// Any thread: node `node` moves at the next apply(). `with_velocity`: its
  /// source reports the velocity itself (set with set_motion), so none is
  /// estimated from the positions.
  void move(std::size_t node, std::optional<Ecef> position, bool with_velocity);

  /// Any thread: the parts of `motion` that are set replace the node's.
  void set_motion(std::size_t node, const position::NodeMotion& motion);

  /// Engine thread: whether set_motion was called since the last call.
  bool motion_changed() { return motion_dirty_.exchange(false, std::memory_order_acq_rel); }

  /// Any thread: every node's velocity and attitude.
  std::vector<position::NodeMotion> motions() const;

  /// Engine thread: applies the waiting positions to `channel` at virtual time
  /// `now_s`, estimating the velocity of those that came without one. True
  /// when any node moved.
  bool apply(double now_s, channel::ChannelMatrix& channel);

 private:
  struct Pending {
    std::optional<Ecef> position;  // nullopt: unknown
    bool with_velocity;
  };
  GeodeticPosition origin_;
  std::mutex pending_mutex_;
  std::vector<std::optional<Pending>> pending_;
  std::atomic<bool> dirty_{false};
  std::atomic<bool> motion_dirty_{false};
  std::vector<position::VelocityEstimator> estimators_;  // engine thread only
  mutable std::mutex motions_mutex_;
  std::vector<position::NodeMotion> motions_;
};

}  // namespace rfsitl::engine
