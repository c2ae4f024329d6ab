#include "mobility_driver.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/scenario/mobility_of.hpp"

namespace rfsitl::engine {

MobilityDriver::MobilityDriver(const scenario::Scenario& s)
    : origin_(s.channel.origin),
      sample_rate_hz_(s.timing.sample_rate_hz),
      interval_(std::max<SampleTime>(
          1, static_cast<SampleTime>(
                 std::llround(s.engine.mobility_update_s * s.timing.sample_rate_hz)))) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& m = s.nodes[i].mobility;
    if (!m) continue;
    const std::string who = "node " + std::to_string(s.nodes[i].id) + " mobility " + m->type;
    try {
      moving_.push_back({i, scenario::make_mobility(s, i, [who](const std::string& line) {
                           spdlog::warn("{}: {}", who, line);
                         })});
    } catch (const std::exception& e) {
      throw std::invalid_argument(who + ": " + e.what());
    }
  }
}

bool MobilityDriver::update(
    SampleTime now, channel::ChannelMatrix& channel,
    const std::function<void(std::size_t, const position::Velocity&)>& velocity) {
  if (moving_.empty() || now < next_) return false;
  const auto t0 = std::chrono::steady_clock::now();
  const double t_s = static_cast<double>(now) / sample_rate_hz_;
  for (const Moving& m : moving_) {
    const position::mobility::MotionState state = m.model->state_at(t_s);
    channel.set_position(m.index, local_to_ecef(state.position, origin_));
    velocity(m.index, state.velocity);
  }
  next_ = now + interval_;
  wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

}  // namespace rfsitl::engine
