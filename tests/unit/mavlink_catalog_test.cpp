// The checksum and the message catalog against a second, by-hand reading of
// the MAVLink serialization spec (https://mavlink.io/en/guide/serialization.html)
// and of common.xml.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mavlink_test_support.hpp"
#include "rfsitl/position/mavlink/checksum.hpp"
#include "rfsitl/position/mavlink/message_catalog.hpp"
#include "rfsitl/position/mavlink/messages.hpp"

namespace rfsitl::position::mavlink {
namespace {

using test::Bytes;
using test::reference_crc;

Bytes text(const std::string& s) {
  return Bytes(s.begin(), s.end());
}

TEST(MavlinkChecksum, IsCrc16Mcrf4xxWithItsCatalogueCheckValue) {
  const Bytes check = text("123456789");
  Checksum c;
  c.add(check);
  EXPECT_EQ(c.value(), 0x6F91);
  EXPECT_EQ(reference_crc(check), 0x6F91);  // the test's own bitwise version agrees
}

TEST(MavlinkChecksum, ByteWiseFormMatchesBitWiseDefinitionOnRandomData) {
  std::mt19937 rng(12);
  for (int n = 0; n < 200; ++n) {
    Bytes data(static_cast<std::size_t>(n));
    for (auto& b : data) b = static_cast<std::uint8_t>(rng());
    Checksum c;
    c.add(data);
    ASSERT_EQ(c.value(), reference_crc(data)) << n << " bytes";
  }
}

// CRC_EXTRA as the spec defines it: the checksum of "NAME " then "type name "
// for each base field in wire order (uint8_t_mavlink_version counts as uint8_t;
// arrays would add a byte holding their length, none here), folded to 8 bits.
std::uint8_t crc_extra_by_hand(const std::string& name, const std::vector<std::string>& fields) {
  std::string s = name + " ";
  for (const std::string& f : fields) s += f + " ";
  const std::uint16_t crc = reference_crc(text(s));
  return static_cast<std::uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

struct HandSpec {
  std::uint32_t id;
  const char* name;
  // Base fields in wire order: common.xml's order stably sorted by size, largest first.
  std::vector<std::string> wire_fields;
  std::uint8_t base_length;
  std::uint8_t max_length;
  std::uint8_t published_crc_extra;  // the value every MAVLink implementation uses
};

const std::vector<HandSpec>& hand_specs() {
  static const std::vector<HandSpec> specs = {
      // XML: type, autopilot, base_mode (u8), custom_mode (u32), system_status,
      // mavlink_version (u8) -> custom_mode first; 4 + 5 = 9 bytes.
      {Heartbeat::kId,
       "HEARTBEAT",
       {"uint32_t custom_mode", "uint8_t type", "uint8_t autopilot", "uint8_t base_mode",
        "uint8_t system_status", "uint8_t mavlink_version"},
       9,
       9,
       50},
      // 13 fields: 3 x u32, then the u16/i16 ones, battery_remaining (i8) last;
      // 12 + 18 + 1 = 31 bytes, extensions 3 x u32 = 43.
      {1,
       "SYS_STATUS",
       {"uint32_t onboard_control_sensors_present", "uint32_t onboard_control_sensors_enabled",
        "uint32_t onboard_control_sensors_health", "uint16_t load", "uint16_t voltage_battery",
        "int16_t current_battery", "uint16_t drop_rate_comm", "uint16_t errors_comm",
        "uint16_t errors_count1", "uint16_t errors_count2", "uint16_t errors_count3",
        "uint16_t errors_count4", "int8_t battery_remaining"},
       31,
       43,
       124},
      // time_usec (u64), fix_type (u8), lat/lon/alt (i32), eph/epv/vel/cog (u16),
      // satellites_visible (u8): 8 + 12 + 8 + 2 = 30; extensions i32, 4 x u32, u16 = 52.
      {GpsRawInt::kId,
       "GPS_RAW_INT",
       {"uint64_t time_usec", "int32_t lat", "int32_t lon", "int32_t alt", "uint16_t eph",
        "uint16_t epv", "uint16_t vel", "uint16_t cog", "uint8_t fix_type",
        "uint8_t satellites_visible"},
       30,
       52,
       24},
      {Attitude::kId,
       "ATTITUDE",
       {"uint32_t time_boot_ms", "float roll", "float pitch", "float yaw", "float rollspeed",
        "float pitchspeed", "float yawspeed"},
       28,
       28,
       39},
      {GlobalPositionInt::kId,
       "GLOBAL_POSITION_INT",
       {"uint32_t time_boot_ms", "int32_t lat", "int32_t lon", "int32_t alt",
        "int32_t relative_alt", "int16_t vx", "int16_t vy", "int16_t vz", "uint16_t hdg"},
       28,
       28,
       104},
      // XML: target_system, target_component, req_stream_id (u8), req_message_rate
      // (u16), start_stop (u8) -> the u16 first.
      {RequestDataStream::kId,
       "REQUEST_DATA_STREAM",
       {"uint16_t req_message_rate", "uint8_t target_system", "uint8_t target_component",
        "uint8_t req_stream_id", "uint8_t start_stop"},
       6,
       6,
       148},
      // XML: target_system, target_component (u8), command (u16), confirmation (u8),
      // param1..7 (float) -> params, command, then the three u8: 28 + 2 + 3 = 33.
      {CommandLong::kId,
       "COMMAND_LONG",
       {"float param1", "float param2", "float param3", "float param4", "float param5",
        "float param6", "float param7", "uint16_t command", "uint8_t target_system",
        "uint8_t target_component", "uint8_t confirmation"},
       33,
       33,
       152},
      // command (u16), result (u8); extensions progress (u8), result_param2 (i32),
      // target_system, target_component (u8): 3 + 7 = 10.
      {CommandAck::kId, "COMMAND_ACK", {"uint16_t command", "uint8_t result"}, 3, 10, 143},
  };
  return specs;
}

TEST(MavlinkCatalog, EntriesOfTheDecodedMessagesMatchADerivationByHand) {
  for (const HandSpec& h : hand_specs()) {
    SCOPED_TRACE(h.name);
    const std::uint8_t derived = crc_extra_by_hand(h.name, h.wire_fields);
    EXPECT_EQ(derived, h.published_crc_extra) << "the hand derivation reproduces the known value";
    const MessageSpec* spec = find_message_spec(h.id);
    ASSERT_NE(spec, nullptr);
    EXPECT_STREQ(spec->name, h.name);
    EXPECT_EQ(spec->crc_extra, derived);
    EXPECT_EQ(spec->base_length, h.base_length);
    EXPECT_EQ(spec->max_length, h.max_length);
  }
}

TEST(MavlinkCatalog, KnowsTheMessagesAutopilotsSendAndIsSortedAndConsistent) {
  for (const std::uint32_t id : {2U, 24U, 32U, 74U, 111U, 147U, 148U, 242U, 244U, 245U, 253U}) {
    EXPECT_NE(find_message_spec(id), nullptr) << id;
  }
  EXPECT_EQ(find_message_spec(0xFFFFFF), nullptr);
  const auto all = message_catalog();
  ASSERT_GT(all.size(), 200U);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_LE(all[i].base_length, all[i].max_length) << all[i].name;
    if (i > 0) {
      EXPECT_LT(all[i - 1].id, all[i].id);
    }
    EXPECT_EQ(find_message_spec(all[i].id), &all[i]);
  }
}

}  // namespace
}  // namespace rfsitl::position::mavlink
