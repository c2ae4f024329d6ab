#pragma once
/// The MAVLink messages this codec decodes and encodes, as plain structs whose
/// field names carry their units (common.xml's units: degE7, mm, cm/s, cdeg,
/// rad, rad/s, us, Hz). Each struct's kId is its message id. The frame they came
/// in (version, sequence, sender) travels beside them: see mavlink_message.hpp.
///
/// Extension fields (those after <extensions> in the XML) are zero when the
/// sender did not send them (MAVLink 1, or an older definition).
#include <array>
#include <cstdint>
#include <limits>

namespace rfsitl::position::mavlink {

/// MAV_TYPE values used by the emulator and its tests.
inline constexpr std::uint8_t kMavTypeGeneric = 0;
inline constexpr std::uint8_t kMavTypeFixedWing = 1;
inline constexpr std::uint8_t kMavTypeQuadrotor = 2;
inline constexpr std::uint8_t kMavTypeGcs = 6;
inline constexpr std::uint8_t kMavTypeOnboardController = 18;

/// MAV_AUTOPILOT values.
inline constexpr std::uint8_t kMavAutopilotGeneric = 0;
inline constexpr std::uint8_t kMavAutopilotArdupilotmega = 3;
inline constexpr std::uint8_t kMavAutopilotInvalid = 8;  ///< not an autopilot (GCS, companion)
inline constexpr std::uint8_t kMavAutopilotPx4 = 12;

/// MAV_STATE values.
inline constexpr std::uint8_t kMavStateStandby = 3;
inline constexpr std::uint8_t kMavStateActive = 4;

/// MAV_CMD values.
inline constexpr std::uint16_t kMavCmdSetMessageInterval = 511;
inline constexpr std::uint16_t kMavCmdRequestMessage = 512;

/// MAV_RESULT values (COMMAND_ACK.result).
inline constexpr std::uint8_t kMavResultAccepted = 0;
inline constexpr std::uint8_t kMavResultTemporarilyRejected = 1;
inline constexpr std::uint8_t kMavResultDenied = 2;
inline constexpr std::uint8_t kMavResultUnsupported = 3;
inline constexpr std::uint8_t kMavResultFailed = 4;

/// MAV_DATA_STREAM values (REQUEST_DATA_STREAM.req_stream_id). ArduPilot sends
/// GLOBAL_POSITION_INT in kPosition and ATTITUDE in kExtra1.
inline constexpr std::uint8_t kMavDataStreamAll = 0;
inline constexpr std::uint8_t kMavDataStreamPosition = 6;
inline constexpr std::uint8_t kMavDataStreamExtra1 = 10;

/// The MAVLink version byte a HEARTBEAT carries (MAVLink 2 and 1.0 both say 3).
inline constexpr std::uint8_t kMavlinkVersionField = 3;

/// HEARTBEAT (0): a system is present; sent at about 1 Hz by every component.
struct Heartbeat {
  static constexpr std::uint32_t kId = 0;
  std::uint8_t type = kMavTypeGeneric;            ///< MAV_TYPE
  std::uint8_t autopilot = kMavAutopilotInvalid;  ///< MAV_AUTOPILOT
  std::uint8_t base_mode = 0;                     ///< MAV_MODE_FLAG bits
  std::uint32_t custom_mode = 0;                  ///< autopilot-specific
  std::uint8_t system_status = kMavStateActive;   ///< MAV_STATE
  std::uint8_t mavlink_version = kMavlinkVersionField;
  bool operator==(const Heartbeat&) const = default;
};

/// GPS_RAW_INT (24): the raw GNSS fix. fix_type < 2 means no position fix; an
/// autopilot may still send GLOBAL_POSITION_INT then (ArduPilot sends zeros).
struct GpsRawInt {
  static constexpr std::uint32_t kId = 24;
  std::uint64_t time_usec = 0;  ///< since boot or Unix epoch
  std::uint8_t fix_type = 0;    ///< GPS_FIX_TYPE: 0-1 no fix, 2 2D, 3 3D, 4+ DGPS/RTK
  std::int32_t lat_e7 = 0;      ///< degrees * 1e7, WGS84
  std::int32_t lon_e7 = 0;      ///< degrees * 1e7, WGS84
  std::int32_t alt_mm = 0;      ///< MSL
  std::uint16_t eph = std::numeric_limits<std::uint16_t>::max();  ///< HDOP * 100; max = unknown
  std::uint16_t epv = std::numeric_limits<std::uint16_t>::max();  ///< VDOP * 100; max = unknown
  std::uint16_t vel_cm_s = std::numeric_limits<std::uint16_t>::max();  ///< ground speed
  std::uint16_t cog_cdeg = std::numeric_limits<std::uint16_t>::max();  ///< course over ground
  std::uint8_t satellites_visible = std::numeric_limits<std::uint8_t>::max();
  // Extensions.
  std::int32_t alt_ellipsoid_mm = 0;  ///< above the WGS84 ellipsoid
  std::uint32_t h_acc_mm = 0;
  std::uint32_t v_acc_mm = 0;
  std::uint32_t vel_acc_mm_s = 0;
  std::uint32_t hdg_acc_degE5 = 0;
  std::uint16_t yaw_cdeg = 0;  ///< 0 = not available, 36000 = north
  bool operator==(const GpsRawInt&) const = default;
};

/// ATTITUDE (30): Euler angles of the body frame (x front, y right, z down).
struct Attitude {
  static constexpr std::uint32_t kId = 30;
  std::uint32_t time_boot_ms = 0;
  float roll_rad = 0.0F;   ///< -pi..pi
  float pitch_rad = 0.0F;  ///< -pi..pi
  float yaw_rad = 0.0F;    ///< -pi..pi, 0 = north, positive clockwise seen from above
  float rollspeed_rad_s = 0.0F;
  float pitchspeed_rad_s = 0.0F;
  float yawspeed_rad_s = 0.0F;
  bool operator==(const Attitude&) const = default;
};

/// GLOBAL_POSITION_INT (33): the autopilot's fused position estimate.
struct GlobalPositionInt {
  static constexpr std::uint32_t kId = 33;
  static constexpr std::uint16_t kHeadingUnknown = std::numeric_limits<std::uint16_t>::max();
  std::uint32_t time_boot_ms = 0;
  std::int32_t lat_e7 = 0;                   ///< degrees * 1e7, WGS84
  std::int32_t lon_e7 = 0;                   ///< degrees * 1e7, WGS84
  std::int32_t alt_mm = 0;                   ///< above mean sea level
  std::int32_t relative_alt_mm = 0;          ///< above home
  std::int16_t vx_cm_s = 0;                  ///< north (NED x)
  std::int16_t vy_cm_s = 0;                  ///< east (NED y)
  std::int16_t vz_cm_s = 0;                  ///< down (NED z)
  std::uint16_t hdg_cdeg = kHeadingUnknown;  ///< 0..35999, or kHeadingUnknown
  bool operator==(const GlobalPositionInt&) const = default;
};

/// REQUEST_DATA_STREAM (66): the legacy way (ArduPilot honours it; PX4 does
/// not) to ask for a group of messages at a rate.
struct RequestDataStream {
  static constexpr std::uint32_t kId = 66;
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint8_t req_stream_id = kMavDataStreamAll;  ///< MAV_DATA_STREAM
  std::uint16_t req_message_rate_hz = 0;
  std::uint8_t start_stop = 1;  ///< 1 start, 0 stop
  bool operator==(const RequestDataStream&) const = default;
};

/// COMMAND_LONG (76): a command with seven float parameters, answered by
/// COMMAND_ACK. param[0] is the XML's param1.
struct CommandLong {
  static constexpr std::uint32_t kId = 76;
  std::uint8_t target_system = 0;
  std::uint8_t target_component = 0;
  std::uint16_t command = 0;      ///< MAV_CMD
  std::uint8_t confirmation = 0;  ///< 0 first transmission, then +1 per retransmission
  std::array<float, 7> param{};
  bool operator==(const CommandLong&) const = default;
};

/// COMMAND_ACK (77): the answer to a COMMAND_LONG.
struct CommandAck {
  static constexpr std::uint32_t kId = 77;
  std::uint16_t command = 0;  ///< MAV_CMD being answered
  std::uint8_t result = 0;    ///< MAV_RESULT
  // Extensions.
  std::uint8_t progress = 0;  ///< percent, for MAV_RESULT_IN_PROGRESS
  std::int32_t result_param2 = 0;
  std::uint8_t target_system = 0;     ///< the system that sent the command
  std::uint8_t target_component = 0;  ///< the component that sent the command
  bool operator==(const CommandAck&) const = default;
};

}  // namespace rfsitl::position::mavlink
