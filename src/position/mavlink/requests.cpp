#include "rfsitl/position/mavlink/requests.hpp"

#include <cmath>
#include <limits>

namespace rfsitl::position::mavlink {

Heartbeat onboard_controller_heartbeat() noexcept {
  Heartbeat h;
  h.type = kMavTypeOnboardController;
  h.autopilot = kMavAutopilotInvalid;
  h.base_mode = 0;
  h.custom_mode = 0;
  h.system_status = kMavStateActive;
  h.mavlink_version = kMavlinkVersionField;
  return h;
}

CommandLong set_message_interval(std::uint8_t target_system, std::uint8_t target_component,
                                 std::uint32_t message_id, std::int32_t interval_us) noexcept {
  CommandLong c;
  c.target_system = target_system;
  c.target_component = target_component;
  c.command = kMavCmdSetMessageInterval;
  c.confirmation = 0;
  c.param[0] = static_cast<float>(message_id);
  c.param[1] = static_cast<float>(interval_us);
  return c;  // param3..7 zero: no index, flight-stack default response target
}

std::int32_t interval_us_for_rate(double rate_hz) noexcept {
  if (!(rate_hz > 0.0)) return -1;  // also NaN
  const double us = std::round(1e6 / rate_hz);
  if (us >= static_cast<double>(std::numeric_limits<std::int32_t>::max())) {
    return std::numeric_limits<std::int32_t>::max();
  }
  return us < 1.0 ? 1 : static_cast<std::int32_t>(us);
}

RequestDataStream request_data_stream(std::uint8_t target_system, std::uint8_t target_component,
                                      std::uint8_t stream_id, std::uint16_t rate_hz,
                                      bool start) noexcept {
  RequestDataStream r;
  r.target_system = target_system;
  r.target_component = target_component;
  r.req_stream_id = stream_id;
  r.req_message_rate_hz = rate_hz;
  r.start_stop = start ? 1 : 0;
  return r;
}

}  // namespace rfsitl::position::mavlink
