#include "phy/gfsk/gfsk_frame.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include "phy/gmsk/frame_format.hpp"
#include "rfsitl/common/crc.hpp"

namespace rfsitl::phy::gfsk {
namespace {

std::uint8_t octet_at(const std::vector<std::int8_t>& s, std::size_t first) {
  std::uint8_t b = 0;
  for (std::size_t i = 0; i < 8; ++i) b = static_cast<std::uint8_t>((b << 1) | (s[first + i] > 0));
  return b;
}

TEST(GfskFrame, PreambleSyncHeaderPayloadAndCrcAreSentMostSignificantBitFirst) {
  const std::vector<std::uint8_t> payload{0x01, 0x80, 0xFF};
  const FrameTag tag{3, 9, 0xDEADBEEFU};
  std::vector<std::int8_t> s(frame_bits(4, payload.size()));
  ASSERT_EQ(build_frame_symbols(4, /*whitening=*/false, tag, payload, s), s.size());
  EXPECT_EQ(s.size(), 8U * (4 + 4 + 10 + 3 + 2));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(octet_at(s, 8 * i), 0xAA);
  EXPECT_EQ(s[0], 1);  // bit 1 is the upper tone
  std::uint32_t sync = 0;
  for (std::size_t i = 0; i < 4; ++i) sync = (sync << 8) | octet_at(s, 32 + 8 * i);
  EXPECT_EQ(sync, kSyncWord);
  const auto header = gmsk::encode_header(gmsk::FrameHeader{tag, payload.size()});
  for (std::size_t i = 0; i < kHeaderBytes; ++i) EXPECT_EQ(octet_at(s, 64 + 8 * i), header[i]);
  for (std::size_t i = 0; i < payload.size(); ++i) EXPECT_EQ(octet_at(s, 144 + 8 * i), payload[i]);
  const std::uint16_t crc = crc16(payload);
  EXPECT_EQ(octet_at(s, 168), crc >> 8);
  EXPECT_EQ(octet_at(s, 176), crc & 0xFF);
}

TEST(GfskFrame, WhiteningXorsPn9OverHeaderPayloadAndCrcOnly) {
  const std::vector<std::uint8_t> payload(20, 0x00);
  std::vector<std::int8_t> plain(frame_bits(8, payload.size()));
  std::vector<std::int8_t> white(plain.size());
  build_frame_symbols(8, false, FrameTag{1, 2, 3}, payload, plain);
  build_frame_symbols(8, true, FrameTag{1, 2, 3}, payload, white);
  const std::size_t start = 8 * (8 + 4);
  for (std::size_t i = 0; i < start; ++i) EXPECT_EQ(plain[i], white[i]);
  gmsk::Whitener pn9;
  for (std::size_t at = start; at < plain.size(); at += 8) {
    EXPECT_EQ(octet_at(white, at), octet_at(plain, at) ^ pn9.next()) << at;
  }
}

TEST(GfskFrame, SyncPatternIsFarFromEveryWholeSymbolShiftOfItself) {
  // What the receiver's 3-error tolerance relies on: the 48-bit pattern (16
  // preamble bits, the sync word) against the stream shifted by s symbols,
  // counting only the bits known there (preamble before, data after unknown).
  const std::uint64_t stream_pre = 0xAAAAAAAAAAAAULL;  // preamble before the pattern
  for (unsigned s = 1; s < kSyncPatternBits; ++s) {
    // Early by s: the window holds s more preamble bits and s fewer sync bits.
    const std::uint64_t early = ((stream_pre << (kSyncPatternBits - s)) | (kSyncPattern >> s)) &
                                ((std::uint64_t{1} << kSyncPatternBits) - 1);
    EXPECT_GE(std::popcount(early ^ kSyncPattern), 13) << "early " << s;
    if (kSyncPatternBits - s >= 24) {  // late by s: compare the known leading bits only
      const std::uint64_t known = (std::uint64_t{1} << (kSyncPatternBits - s)) - 1;
      const std::uint64_t late = kSyncPattern & known;
      EXPECT_GE(std::popcount(late ^ ((kSyncPattern >> s) & known)), 13) << "late " << s;
    }
  }
}

}  // namespace
}  // namespace rfsitl::phy::gfsk
