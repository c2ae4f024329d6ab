// MavlinkEncoder and the request builders: every message through the parser
// and back, v2 truncation, v1 base-only payloads, the sequence counter.
#include "rfsitl/position/mavlink/encoder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "mavlink_test_support.hpp"
#include "rfsitl/position/mavlink/message_catalog.hpp"
#include "rfsitl/position/mavlink/requests.hpp"

namespace rfsitl::position::mavlink {
namespace {

using test::Bytes;
using test::parse;

// Every field non-zero, so that a field lost or swapped in either direction shows.
Heartbeat sample(Heartbeat) {
  return {.type = kMavTypeQuadrotor,
          .autopilot = kMavAutopilotArdupilotmega,
          .base_mode = 0x81,
          .custom_mode = 0x01020304,
          .system_status = kMavStateActive,
          .mavlink_version = 3};
}
GpsRawInt sample(GpsRawInt) {
  return {.time_usec = 1234567890123ULL,
          .fix_type = 3,
          .lat_e7 = 430008000,
          .lon_e7 = -787890000,
          .alt_mm = 250000,
          .eph = 120,
          .epv = 180,
          .vel_cm_s = 1500,
          .cog_cdeg = 27000,
          .satellites_visible = 14,
          .alt_ellipsoid_mm = 250100,
          .h_acc_mm = 800,
          .v_acc_mm = 1200,
          .vel_acc_mm_s = 300,
          .hdg_acc_degE5 = 4500,
          .yaw_cdeg = 18000};
}
Attitude sample(Attitude) {
  return {.time_boot_ms = 4242,
          .roll_rad = 0.1F,
          .pitch_rad = -0.2F,
          .yaw_rad = 3.0F,
          .rollspeed_rad_s = 0.01F,
          .pitchspeed_rad_s = -0.02F,
          .yawspeed_rad_s = 0.5F};
}
GlobalPositionInt sample(GlobalPositionInt) {
  return {.time_boot_ms = 4242,
          .lat_e7 = 430008000,
          .lon_e7 = -787890000,
          .alt_mm = 250000,
          .relative_alt_mm = 10000,
          .vx_cm_s = 150,
          .vy_cm_s = -20,
          .vz_cm_s = 5,
          .hdg_cdeg = 9000};
}
RequestDataStream sample(RequestDataStream) {
  return {.target_system = 1,
          .target_component = 1,
          .req_stream_id = kMavDataStreamPosition,
          .req_message_rate_hz = 10,
          .start_stop = 1};
}
CommandLong sample(CommandLong) {
  return {.target_system = 1,
          .target_component = 1,
          .command = kMavCmdSetMessageInterval,
          .confirmation = 2,
          .param = {33.0F, 200000.0F, 3, 4, 5, 6, 7}};
}
CommandAck sample(CommandAck) {
  return {.command = kMavCmdSetMessageInterval,
          .result = kMavResultDenied,
          .progress = 50,
          .result_param2 = -7,
          .target_system = 255,
          .target_component = 190};
}

// v1 carries only the base fields: the extension fields read back as zero.
template <class T>
T without_extensions(T m) {
  return m;
}
GpsRawInt without_extensions(GpsRawInt m) {
  const GpsRawInt zeros{};
  m.alt_ellipsoid_mm = zeros.alt_ellipsoid_mm;
  m.h_acc_mm = zeros.h_acc_mm;
  m.v_acc_mm = zeros.v_acc_mm;
  m.vel_acc_mm_s = zeros.vel_acc_mm_s;
  m.hdg_acc_degE5 = zeros.hdg_acc_degE5;
  m.yaw_cdeg = zeros.yaw_cdeg;
  return m;
}
CommandAck without_extensions(CommandAck m) {
  m.progress = 0;
  m.result_param2 = 0;
  m.target_system = 0;
  m.target_component = 0;
  return m;
}

template <class T>
class MavlinkRoundTrip : public ::testing::Test {};
using Encodable = ::testing::Types<Heartbeat, GpsRawInt, Attitude, GlobalPositionInt,
                                   RequestDataStream, CommandLong, CommandAck>;
TYPED_TEST_SUITE(MavlinkRoundTrip, Encodable);

TYPED_TEST(MavlinkRoundTrip, V2CarriesEveryFieldAndTheSender) {
  const TypeParam message = sample(TypeParam{});
  MavlinkEncoder enc(42, 191, 200);
  const Bytes frame = enc.encode(message);
  const MessageSpec* spec = find_message_spec(TypeParam::kId);
  ASSERT_NE(spec, nullptr);
  EXPECT_EQ(frame.size(), kHeaderBytesV2 + spec->max_length + kChecksumBytes)
      << "no trailing zero in the sample, so nothing truncated";
  const auto r = parse(frame);
  ASSERT_EQ(r.messages.size(), 1U);
  const FrameInfo& info = r.messages[0].frame;
  EXPECT_EQ(info.version, MavlinkVersion::kV2);
  EXPECT_EQ(info.sysid, 42);
  EXPECT_EQ(info.compid, 191);
  EXPECT_EQ(info.seq, 200);
  EXPECT_EQ(info.msgid, TypeParam::kId);
  const auto* decoded = r.messages[0].template get<TypeParam>();
  ASSERT_NE(decoded, nullptr);
  EXPECT_EQ(*decoded, message);
}

TYPED_TEST(MavlinkRoundTrip, V1CarriesTheBaseFields) {
  const TypeParam message = sample(TypeParam{});
  MavlinkEncoder enc(3, 1);
  const Bytes frame = enc.encode(message, MavlinkVersion::kV1);
  const MessageSpec* spec = find_message_spec(TypeParam::kId);
  ASSERT_NE(spec, nullptr);
  EXPECT_EQ(frame.size(), kHeaderBytesV1 + spec->base_length + kChecksumBytes);
  const auto r = parse(frame);
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.messages[0].frame.version, MavlinkVersion::kV1);
  const auto* decoded = r.messages[0].template get<TypeParam>();
  ASSERT_NE(decoded, nullptr);
  EXPECT_EQ(*decoded, without_extensions(message));
}

TYPED_TEST(MavlinkRoundTrip, AllZeroMessageTruncatesToOneByteAndReadsBackAsZero) {
  // A payload of one zero byte is the smallest a v2 sender may emit: every
  // field reads as zero, and encoding that message gives the one byte back.
  MavlinkEncoder enc(1, 1);
  Bytes frame = test::v2_frame(TypeParam::kId, find_message_spec(TypeParam::kId)->crc_extra, {0});
  const auto r = parse(frame);
  ASSERT_EQ(r.messages.size(), 1U);
  const auto* decoded = r.messages[0].template get<TypeParam>();
  ASSERT_NE(decoded, nullptr);
  const Bytes reencoded = enc.encode(*decoded);
  EXPECT_EQ(reencoded.size(), kHeaderBytesV2 + 1 + kChecksumBytes);
  EXPECT_EQ(reencoded[1], 1) << "len";
  EXPECT_EQ(reencoded[kHeaderBytesV2], 0);
}

TEST(MavlinkEncoder, V2DropsTrailingZerosOnly) {
  GlobalPositionInt p = sample(GlobalPositionInt{});
  p.hdg_cdeg = 0;
  p.vz_cm_s = 0;
  p.vy_cm_s = 0x0100;  // low byte zero, high byte not: the cut stops there
  MavlinkEncoder enc(1, 1);
  const Bytes frame = enc.encode(p);
  EXPECT_EQ(frame[1], 24) << "28 bytes minus hdg (2), vz (2)";
  const auto r = parse(frame);
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(*r.messages[0].get<GlobalPositionInt>(), p);
}

TEST(MavlinkEncoder, SequenceCounterAdvancesPerFrameAndWraps) {
  MavlinkEncoder enc(1, 1, 254);
  const Heartbeat hb = onboard_controller_heartbeat();
  EXPECT_EQ(enc.encode(hb)[4], 254);
  EXPECT_EQ(enc.encode(hb, MavlinkVersion::kV1)[2], 255);
  EXPECT_EQ(enc.encode(set_message_interval(1, 1, 30, 100000))[4], 0);
  EXPECT_EQ(enc.next_seq(), 1);
}

TEST(MavlinkRequests, OnboardHeartbeatIsAnOnboardControllerWithoutAutopilot) {
  const Heartbeat hb = onboard_controller_heartbeat();
  EXPECT_EQ(hb.type, 18);
  EXPECT_EQ(hb.autopilot, 8);
  EXPECT_EQ(hb.base_mode, 0);
  EXPECT_EQ(hb.custom_mode, 0U);
  EXPECT_EQ(hb.system_status, kMavStateActive);
  EXPECT_EQ(hb.mavlink_version, 3);
}

TEST(MavlinkRequests, SetMessageIntervalPutsIdAndIntervalInParams1And2) {
  const CommandLong c = set_message_interval(7, 1, GlobalPositionInt::kId, 250000);
  EXPECT_EQ(c.command, 511);
  EXPECT_EQ(c.target_system, 7);
  EXPECT_EQ(c.target_component, 1);
  EXPECT_EQ(c.param[0], 33.0F);
  EXPECT_EQ(c.param[1], 250000.0F);
  for (std::size_t i = 2; i < 7; ++i) EXPECT_EQ(c.param[i], 0.0F);
  EXPECT_EQ(set_message_interval(1, 1, 30, -1).param[1], -1.0F);
}

TEST(MavlinkRequests, IntervalForRate) {
  EXPECT_EQ(interval_us_for_rate(4.0), 250000);
  EXPECT_EQ(interval_us_for_rate(3.0), 333333);
  EXPECT_EQ(interval_us_for_rate(0.0), -1);
  EXPECT_EQ(interval_us_for_rate(-2.0), -1);
  EXPECT_EQ(interval_us_for_rate(std::nan("")), -1);
  EXPECT_EQ(interval_us_for_rate(1e9), 1);
  EXPECT_EQ(interval_us_for_rate(1e-9), 2147483647);
}

TEST(MavlinkRequests, RequestDataStreamStartAndStop) {
  const RequestDataStream start = request_data_stream(1, 0, kMavDataStreamExtra1, 25, true);
  EXPECT_EQ(start.req_stream_id, 10);
  EXPECT_EQ(start.req_message_rate_hz, 25);
  EXPECT_EQ(start.start_stop, 1);
  EXPECT_EQ(request_data_stream(1, 0, kMavDataStreamAll, 0, false).start_stop, 0);
}

}  // namespace
}  // namespace rfsitl::position::mavlink
