#include "node_state_inbox.hpp"

#include "rfsitl/channel/geodesy.hpp"

namespace rfsitl::engine {

NodeStateInbox::NodeStateInbox(std::size_t nodes, GeodeticPosition origin)
    : origin_(origin), pending_(nodes), estimators_(nodes), motions_(nodes) {}

void NodeStateInbox::move(std::size_t node, std::optional<Ecef> position, bool with_velocity) {
  std::lock_guard lock(pending_mutex_);
  pending_[node].emplace(Pending{position, with_velocity});
  dirty_.store(true, std::memory_order_release);
}

void NodeStateInbox::set_motion(std::size_t node, const position::NodeMotion& motion) {
  if (!motion.velocity && !motion.attitude) return;
  std::lock_guard lock(motions_mutex_);
  if (motion.velocity) motions_[node].velocity = motion.velocity;
  if (motion.attitude) motions_[node].attitude = motion.attitude;
  motion_dirty_.store(true, std::memory_order_release);
}

std::vector<position::NodeMotion> NodeStateInbox::motions() const {
  std::lock_guard lock(motions_mutex_);
  return motions_;
}

bool NodeStateInbox::apply(double now_s, channel::ChannelMatrix& channel) {
  if (!dirty_.exchange(false, std::memory_order_acq_rel)) return false;
  std::lock_guard lock(pending_mutex_);
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    if (!pending_[i]) continue;
    const auto [position, with_velocity] = *pending_[i];
    pending_[i].reset();
    channel.set_position(i, position);
    if (with_velocity) continue;
    // Positions only: the velocity is estimated from them on the engine's clock.
    std::optional<position::Velocity> v;
    if (position) {
      v = estimators_[i].update(now_s, channel::ecef_to_local(*position, origin_));
    } else {
      estimators_[i].reset();
    }
    std::lock_guard motion_lock(motions_mutex_);
    motions_[i].velocity = v;
  }
  return true;
}

}  // namespace rfsitl::engine
