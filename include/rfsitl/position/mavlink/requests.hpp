#pragma once
/// The messages the emulator sends a vehicle to get its position stream: its
/// own HEARTBEAT (autopilots stream only to links they have heard from, and
/// ArduPilot and PX4 both want a heartbeat on the link), and the two ways to
/// ask for a message rate. Pure functions; encode with MavlinkEncoder.
#include <cstdint>

#include "rfsitl/position/mavlink/messages.hpp"

namespace rfsitl::position::mavlink {

/// The HEARTBEAT of an onboard component that is not an autopilot:
/// MAV_TYPE_ONBOARD_CONTROLLER (18), MAV_AUTOPILOT_INVALID (8), base and custom
/// mode 0, MAV_STATE_ACTIVE.
Heartbeat onboard_controller_heartbeat() noexcept;

/// COMMAND_LONG MAV_CMD_SET_MESSAGE_INTERVAL (511): send message `message_id` every
/// `interval_us` microseconds (-1 stops it, 0 asks for the default rate).
/// param1 and param2 are floats on the wire, exact for intervals up to 2^24 us
/// (16.7 s); longer ones are rounded to the nearest float. param7 0: to the
/// flight stack's default address.
CommandLong set_message_interval(std::uint8_t target_system, std::uint8_t target_component,
                                 std::uint32_t message_id, std::int32_t interval_us) noexcept;

/// The interval (us) for `rate_hz` messages per second, as
/// set_message_interval wants it: -1 (stop) for a rate <= 0, else
/// round(1e6 / rate_hz), at least 1.
std::int32_t interval_us_for_rate(double rate_hz) noexcept;

/// REQUEST_DATA_STREAM (66): start (`start` true) or stop the group
/// `stream_id` (MAV_DATA_STREAM) at `rate_hz` messages per second.
RequestDataStream request_data_stream(std::uint8_t target_system, std::uint8_t target_component,
                                      std::uint8_t stream_id, std::uint16_t rate_hz,
                                      bool start) noexcept;

}  // namespace rfsitl::position::mavlink
