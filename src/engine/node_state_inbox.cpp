#include "node_state_inbox.hpp"

#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::engine {

NodeStateInbox::NodeStateInbox(std::size_t nodes, GeodeticPosition origin)
    : origin_(origin), pending_(nodes), estimators_(nodes), motions_(nodes) {}

void NodeStateInbox::move(std::size_t node, std::optional<Ecef> position, bool with_velocity) {
  std::lock_guard lock(pending_mutex_);
  StateUpdate& u = pending_[node].emplace(pending_[node].value_or(StateUpdate{}));
  u.node = static_cast<std::uint32_t>(node);
  u.moves = true;
  u.position = position;
  u.with_velocity = with_velocity;
  dirty_.store(true, std::memory_order_release);
}

void NodeStateInbox::set_motion(std::size_t node, const position::NodeMotion& motion) {
  if (!motion.velocity && !motion.attitude) return;
  std::lock_guard lock(pending_mutex_);
  StateUpdate& u = pending_[node].emplace(pending_[node].value_or(StateUpdate{}));
  u.node = static_cast<std::uint32_t>(node);
  if (motion.velocity) u.motion.velocity = motion.velocity;
  if (motion.attitude) u.motion.attitude = motion.attitude;
  dirty_.store(true, std::memory_order_release);
}

void NodeStateInbox::set_motion_now(std::size_t node, const position::NodeMotion& motion) {
  if (!motion.velocity && !motion.attitude) return;
  std::lock_guard lock(motions_mutex_);
  if (motion.velocity) motions_[node].velocity = motion.velocity;
  if (motion.attitude) motions_[node].attitude = motion.attitude;
  motion_dirty_.store(true, std::memory_order_release);
}

std::vector<StateUpdate> NodeStateInbox::take() {
  std::vector<StateUpdate> out;
  if (!dirty_.exchange(false, std::memory_order_acq_rel)) return out;
  std::lock_guard lock(pending_mutex_);
  for (auto& p : pending_) {
    if (!p) continue;
    out.push_back(*p);
    p.reset();
  }
  return out;
}

bool NodeStateInbox::apply(std::span<const StateUpdate> updates, double now_s,
                           channel::ChannelMatrix& channel) {
  bool moved = false;
  for (const StateUpdate& u : updates) {
    const std::size_t i = u.node;
    if (u.moves) {
      moved = true;
      channel.set_position(i, u.position);
      if (!u.with_velocity) {
        // Positions only: the velocity is estimated from them on the engine's clock.
        std::optional<position::Velocity> v;
        if (u.position) {
          v = estimators_[i].update(now_s, ecef_to_local(*u.position, origin_));
        } else {
          estimators_[i].reset();
        }
        std::lock_guard motion_lock(motions_mutex_);
        motions_[i].velocity = v;
      }
    }
    set_motion_now(i, u.motion);
  }
  return moved;
}

std::vector<position::NodeMotion> NodeStateInbox::motions() const {
  std::lock_guard lock(motions_mutex_);
  return motions_;
}

}  // namespace rfsitl::engine
