// MavlinkParser on streams with everything a link can throw at it: garbage,
// corrupt and cut frames, both versions, signatures, truncated and extended
// payloads, unknown ids and flags, in any chunking.
#include "rfsitl/position/mavlink/parser.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "mavlink_test_support.hpp"

namespace rfsitl::position::mavlink {
namespace {

using test::Bytes;
using test::concat;
using test::parse;
using test::v1_frame;
using test::v2_frame;

constexpr std::uint8_t kHeartbeatExtra = 50;
constexpr std::uint8_t kGlobalPositionIntExtra = 104;
constexpr std::uint8_t kSystemTimeExtra = 137;
constexpr std::uint32_t kSystemTimeId = 2;
constexpr std::uint8_t kUnknownV1Id = 3;  // not defined in any dialect we know

// HEARTBEAT payload in wire order: custom_mode (u32), type, autopilot,
// base_mode, system_status, mavlink_version.
Bytes heartbeat_payload(std::uint32_t custom_mode, std::uint8_t type = kMavTypeQuadrotor) {
  Bytes p;
  test::put_u32(p, custom_mode);
  for (const std::uint8_t b :
       {type, kMavAutopilotArdupilotmega, std::uint8_t{0x51}, kMavStateActive, std::uint8_t{3}}) {
    test::put_u8(p, b);
  }
  return p;
}

Bytes heartbeat_v1(std::uint32_t custom_mode, std::uint8_t seq = 0) {
  return v1_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(custom_mode), seq);
}

Bytes heartbeat_v2(std::uint32_t custom_mode, std::uint8_t seq = 0) {
  return v2_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(custom_mode), seq);
}

// GLOBAL_POSITION_INT payload with every field set (28 bytes, no zero at its end).
Bytes position_payload() {
  Bytes p;
  for (const std::uint32_t v :
       {1000U, 430008000U, static_cast<std::uint32_t>(-787890000), 250000U, 10000U}) {
    test::put_u32(p, v);
  }
  for (const std::uint16_t v :
       {std::uint16_t{150}, std::uint16_t{0xFFEC}, std::uint16_t{5}, std::uint16_t{9000}}) {
    test::put_u16(p, v);
  }
  return p;
}

std::uint32_t custom_mode_of(const MavlinkMessage& m) {
  const auto* hb = m.get<Heartbeat>();
  return hb == nullptr ? 0xDEADBEEF : hb->custom_mode;
}

Bytes garbage(std::size_t n, std::uint32_t seed) {
  // No magic bytes, so every byte is garbage whatever the parser's policy.
  std::mt19937 rng(seed);
  Bytes g(n);
  for (auto& b : g) {
    do {
      b = static_cast<std::uint8_t>(rng());
    } while (b == kMagicV1 || b == kMagicV2);
  }
  return g;
}

TEST(MavlinkParser, GarbageBeforeAndBetweenFramesIsCountedAndSkipped) {
  const Bytes stream =
      concat({garbage(37, 1), heartbeat_v2(1), garbage(5, 2), heartbeat_v1(2), garbage(11, 3)});
  const auto r = parse(stream);
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 1U);
  EXPECT_EQ(custom_mode_of(r.messages[1]), 2U);
  EXPECT_EQ(r.counters.garbage_bytes, 37U + 5U + 11U);
  EXPECT_EQ(r.counters.frames, 2U);
  EXPECT_EQ(r.counters.frame_bytes, 21U + 17U);
  EXPECT_EQ(r.buffered, 0U);
}

TEST(MavlinkParser, BadCrcFrameIsDroppedAndTheNextFrameFound) {
  Bytes corrupt = heartbeat_v2(1);
  corrupt[12] ^= 0x40;  // a payload bit flipped in transit
  const auto r = parse(concat({corrupt, heartbeat_v2(2)}));
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 2U);
  EXPECT_EQ(r.counters.bad_crc, 1U);
  // The rejected candidate's bytes were rescanned and hold no frame: all of
  // them (its magic byte included) are the rejected frame's, none garbage.
  EXPECT_EQ(r.counters.rejected_bytes, corrupt.size());
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, AFrameCutShortDoesNotHideTheNextOne) {
  const Bytes first = heartbeat_v2(1);
  const Bytes cut(first.begin(), first.begin() + 12);  // the link lost the rest
  // The cut frame's candidate takes the next frame's first bytes as its
  // payload and fails its checksum; the rescan finds the next frame.
  const auto r = parse(concat({cut, heartbeat_v2(2), heartbeat_v1(3)}));
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[1]), 3U);
  EXPECT_EQ(r.counters.bad_crc, 1U);
  EXPECT_EQ(r.counters.rejected_bytes, cut.size());
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, FrameInsideAFalseCandidateIsFound) {
  // A magic byte in noise claims a 200-byte GLOBAL_POSITION_INT; the real frame
  // lies within its would-be payload.
  Bytes fake_header = {kMagicV2, 200, 0, 0, 0, 1, 1, 33, 0, 0};
  const Bytes real = heartbeat_v1(7);
  const Bytes padding = garbage(200 + 2 - real.size(), 4);
  const auto r = parse(concat({fake_header, real, padding, heartbeat_v2(8)}));
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 7U);
  EXPECT_EQ(custom_mode_of(r.messages[1]), 8U);
  EXPECT_EQ(r.counters.bad_crc, 1U);
  // The candidate claimed all of the padding too.
  EXPECT_EQ(r.counters.rejected_bytes, fake_header.size() + padding.size());
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, V1AndV2MixedInOneStreamKeepTheirFrameInfo) {
  const auto r = parse(concat({heartbeat_v1(1, 10), heartbeat_v2(2, 11), heartbeat_v1(3, 12)}));
  ASSERT_EQ(r.messages.size(), 3U);
  const MavlinkVersion versions[] = {MavlinkVersion::kV1, MavlinkVersion::kV2, MavlinkVersion::kV1};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.messages[i].frame.version, versions[i]);
    EXPECT_EQ(r.messages[i].frame.seq, 10 + i);
    EXPECT_EQ(r.messages[i].frame.sysid, 1);
    EXPECT_EQ(r.messages[i].frame.msgid, Heartbeat::kId);
    EXPECT_EQ(custom_mode_of(r.messages[i]), i + 1);
  }
}

TEST(MavlinkParser, SignedV2FrameIsAcceptedWithItsSignatureSkipped) {
  // The signature's bytes include magic values: they must not be scanned.
  const Bytes signature = {0x01, 0xFD, 0xFE, 0x00, 0x00, 0x00, 0x00,
                           0xFD, 0x09, 0xFE, 0x09, 0xAA, 0x55};
  const Bytes signed_frame = v2_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(5), 0, 1,
                                      1, kIncompatSigned, signature);
  const auto r = parse(concat({signed_frame, heartbeat_v2(6)}));
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_TRUE(r.messages[0].frame.is_signed);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 5U);
  EXPECT_FALSE(r.messages[1].frame.is_signed);
  EXPECT_EQ(r.counters.frame_bytes, signed_frame.size() + 21U);
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, TruncatedV2PayloadIsZeroExtended) {
  Bytes full = position_payload();
  full.resize(13);  // time, lat, lon and alt's first byte: a sender drops trailing
  full[12] = 0x07;  // zeros only, so pretend alt = 7 and everything after it is zero
  const auto r = parse(v2_frame(GlobalPositionInt::kId, kGlobalPositionIntExtra, full));
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.messages[0].frame.payload_length, 13);
  const auto* p = r.messages[0].get<GlobalPositionInt>();
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->time_boot_ms, 1000U);
  EXPECT_EQ(p->lat_e7, 430008000);
  EXPECT_EQ(p->lon_e7, -787890000);
  EXPECT_EQ(p->alt_mm, 7);
  EXPECT_EQ(p->relative_alt_mm, 0);
  EXPECT_EQ(p->vx_cm_s, 0);
  EXPECT_EQ(p->hdg_cdeg, 0);
}

TEST(MavlinkParser, LongerV2PayloadFromANewerDefinitionIsAccepted) {
  Bytes payload = heartbeat_payload(9);
  payload.insert(payload.end(), {0x11, 0x22, 0x33});  // extensions we do not know
  const auto r =
      parse(concat({v2_frame(Heartbeat::kId, kHeartbeatExtra, payload), heartbeat_v2(10)}));
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 9U);
  EXPECT_EQ(r.messages[0].frame.payload_length, 12);
}

TEST(MavlinkParser, V1FrameWithTheWrongLengthIsDropped) {
  Bytes short_payload = heartbeat_payload(1);
  short_payload.pop_back();
  const auto r =
      parse(concat({v1_frame(Heartbeat::kId, kHeartbeatExtra, short_payload), heartbeat_v1(2)}));
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 2U);
  EXPECT_EQ(r.counters.bad_length, 1U);
  EXPECT_EQ(r.counters.bad_crc, 0U);
}

TEST(MavlinkParser, UnknownIdsAreSkippedWholeAndCounted) {
  // A v2 frame of an id no dialect here defines, whose payload holds a complete
  // frame-like byte sequence: skipped whole, not rescanned.
  const Bytes inner = heartbeat_v1(99);
  const Bytes unknown_v2 = v2_frame(0x123456, 0, inner);
  const Bytes unknown_v1 = v1_frame(kUnknownV1Id, 0, {1, 2, 3});
  const auto r = parse(concat({unknown_v2, heartbeat_v2(1), unknown_v1, heartbeat_v1(2)}));
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 1U);
  EXPECT_EQ(custom_mode_of(r.messages[1]), 2U);
  EXPECT_EQ(r.counters.unknown_id, 2U);
  EXPECT_EQ(r.counters.unknown_id_bytes, unknown_v2.size() + unknown_v1.size());
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, SignedUnknownIdFrameIsSkippedWithItsSignature) {
  const Bytes unknown = v2_frame(0x0A0B0C, 0, {1, 2}, 0, 1, 1, kIncompatSigned, Bytes(13, 0xFD));
  const auto r = parse(concat({unknown, heartbeat_v2(3)}));
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.counters.unknown_id_bytes, unknown.size());
}

TEST(MavlinkParser, UnknownIncompatFlagsDropTheFrame) {
  const Bytes flagged =
      v2_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(1), 0, 1, 1, 0x02);
  const auto r = parse(concat({flagged, heartbeat_v2(2)}));
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(custom_mode_of(r.messages[0]), 2U);
  EXPECT_EQ(r.counters.bad_incompat_flags, 1U);
  EXPECT_EQ(r.counters.rejected_bytes, flagged.size());
  EXPECT_EQ(r.counters.garbage_bytes, 0U);
}

TEST(MavlinkParser, KnownButUndecodedMessageKeepsItsPayload) {
  Bytes payload;
  test::put_u32(payload, 0x89ABCDEF);  // time_unix_usec, low half
  test::put_u32(payload, 0x01234567);  // time_unix_usec, high half
  test::put_u32(payload, 4242);        // time_boot_ms
  const auto r = parse(v2_frame(kSystemTimeId, kSystemTimeExtra, payload));
  ASSERT_EQ(r.messages.size(), 1U);
  const auto* raw = r.messages[0].get<UndecodedMessage>();
  ASSERT_NE(raw, nullptr);
  EXPECT_EQ(raw->msgid, kSystemTimeId);
  EXPECT_EQ(raw->length, 12);
  EXPECT_TRUE(std::equal(payload.begin(), payload.end(), raw->payload.begin()));
}

TEST(MavlinkParser, ResetDiscardsAPartialFrameAsTruncated) {
  MavlinkParser parser;
  std::vector<MavlinkMessage> out;
  const Bytes frame = heartbeat_v2(1);
  parser.feed(std::span(frame).first(15), out);
  EXPECT_EQ(parser.buffered(), 15U);
  parser.reset();
  EXPECT_EQ(parser.buffered(), 0U);
  EXPECT_EQ(parser.counters().truncated, 1U);
  EXPECT_EQ(parser.counters().garbage_bytes, 15U);
  parser.feed(heartbeat_v2(2), out);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(custom_mode_of(out[0]), 2U);
}

TEST(MavlinkParser, ResultDoesNotDependOnHowTheStreamIsCut) {
  Bytes corrupt = heartbeat_v1(4);
  corrupt.back() ^= 0xFF;
  Bytes truncated_position = position_payload();
  truncated_position.resize(20);
  const Bytes stream = concat({
      garbage(9, 5), heartbeat_v2(1), Bytes{kMagicV2, kMagicV1},  // stray magic bytes
      v2_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(2), 1, 1, 1, kIncompatSigned,
               Bytes(13, 0x5A)),
      v2_frame(0x123456, 0, Bytes(40, kMagicV1)), corrupt, heartbeat_v1(3),
      v2_frame(GlobalPositionInt::kId, kGlobalPositionIntExtra, truncated_position),
      v2_frame(Heartbeat::kId, kHeartbeatExtra, heartbeat_payload(5), 0, 1, 1, 0x80),
      v1_frame(kUnknownV1Id, 0, Bytes(7, kMagicV2)), heartbeat_v2(6),
      Bytes{kMagicV2, 0x09, 0x00},  // a frame still arriving at the end
  });
  const auto whole = parse(stream);
  EXPECT_EQ(whole.messages.size(), 5U);
  EXPECT_EQ(whole.counters.bad_crc, 1U);
  EXPECT_EQ(whole.counters.unknown_id, 2U);
  // The stray FD reads FE as its length and the next frame's FD as its flags;
  // the stray FE then claims a 0xFD-byte SYS_STATUS (31 in v1): both rejected.
  EXPECT_EQ(whole.counters.bad_incompat_flags, 2U);
  EXPECT_EQ(whole.counters.bad_length, 1U);
  EXPECT_EQ(whole.buffered, 3U);
  for (const std::size_t chunk : {1U, 2U, 3U, 7U, 10U, 13U, 64U, 281U}) {
    const auto cut = parse(stream, chunk);
    EXPECT_EQ(cut.messages, whole.messages) << "chunk " << chunk;
    EXPECT_EQ(cut.counters, whole.counters) << "chunk " << chunk;
    EXPECT_EQ(cut.buffered, whole.buffered) << "chunk " << chunk;
  }
}

TEST(MavlinkParser, RandomBytesKeepMemoryBoundedAndEveryByteAccountedFor) {
  // parse() checks buffered() <= kMaxFrameBytes and the byte accounting after
  // every read; magic bytes are made common so that many candidates form.
  std::mt19937 rng(77);
  for (int round = 0; round < 20; ++round) {
    Bytes noise(4000);
    for (auto& b : noise) {
      const auto r = rng();
      b = (r & 7U) == 0 ? kMagicV2 : (r & 7U) == 1 ? kMagicV1 : static_cast<std::uint8_t>(r >> 8);
    }
    const auto whole = parse(noise);
    const auto bytewise = parse(noise, 1);
    EXPECT_EQ(whole.messages, bytewise.messages);
    EXPECT_EQ(whole.counters, bytewise.counters);
  }
}

}  // namespace
}  // namespace rfsitl::position::mavlink
