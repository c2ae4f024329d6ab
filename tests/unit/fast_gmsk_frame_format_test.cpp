#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string_view>
#include <vector>

#include "phy/gmsk/crc.hpp"
#include "phy/gmsk/frame_format.hpp"

namespace rfsitl::phy::gmsk {
namespace {

std::vector<std::uint8_t> bytes_of(std::string_view s) {
  return {s.begin(), s.end()};
}

TEST(FastGmskCrc, MatchesTheStandardCheckValues) {
  const auto check = bytes_of("123456789");
  EXPECT_EQ(crc16(check), 0x29B1);
  EXPECT_EQ(crc32(check), 0xCBF43926U);
  EXPECT_EQ(crc32({}), 0U);
}

TEST(FastGmskWhitener, IsTheMaximalLengthPn9Sequence) {
  // 511 octets hold 8 full periods of a 511-bit sequence; a maximal-length one
  // has 256 ones per period and repeats after exactly 511 bits.
  std::vector<int> bits;
  Whitener w;
  for (int i = 0; i < 2 * 511 / 8 + 2; ++i) {
    const std::uint8_t b = w.next();
    for (int j = 0; j < 8; ++j) bits.push_back((b >> j) & 1);
  }
  int ones = 0;
  for (int i = 0; i < 511; ++i) ones += bits[i];
  EXPECT_EQ(ones, 256);
  for (int i = 0; i < 511; ++i) ASSERT_EQ(bits[i], bits[i + 511]) << i;
  for (int p = 1; p < 511; ++p) {
    bool same = true;
    for (int i = 0; i < 511 && same; ++i) same = bits[i] == bits[i + p];
    ASSERT_FALSE(same) << "period " << p;
  }
}

TEST(FastGmskFrameFormat, HeaderRoundTripsAndAnyFlippedBitFailsItsCrc) {
  const FrameHeader h{FrameTag{7, 255, 0xDEADBEEFU}, 65535};
  auto b = encode_header(h);
  const auto back = decode_header(b);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->tag.src, 7);
  EXPECT_EQ(back->tag.dst, 255);
  EXPECT_EQ(back->tag.serial, 0xDEADBEEFU);
  EXPECT_EQ(back->payload_bytes, 65535U);
  for (std::size_t bit = 0; bit < 8 * kHeaderBytes; ++bit) {
    auto bad = b;
    bad[bit / 8] = static_cast<std::uint8_t>(bad[bit / 8] ^ (1U << (bit % 8)));
    EXPECT_FALSE(decode_header(bad).has_value()) << "bit " << bit;
  }
}

TEST(FastGmskFrameFormat, FrameSymbolsStartWithPeriodicPreambleThenSyncWord) {
  const std::vector<std::uint8_t> payload = {1, 2, 3};
  std::vector<std::int8_t> a(frame_symbol_count(payload.size()) + 5, 0);
  ASSERT_EQ(build_frame_symbols(FrameTag{1, 2, 3}, payload, a), frame_symbol_count(3));
  EXPECT_EQ(frame_symbol_count(3), 64U + 32U + 80U + 8U * 7U + 2U);
  // Undo the precoding a_n = c_n c_{n-1} (c_{-1} = +1) to get the pseudo-symbols.
  std::vector<int> c;
  int prev = 1;
  for (std::size_t n = 0; n < frame_symbol_count(3); ++n) {
    ASSERT_TRUE(a[n] == 1 || a[n] == -1);
    prev *= a[n];
    c.push_back(prev);
  }
  for (std::size_t n = 0; n < kPreambleSymbols; ++n) {
    EXPECT_EQ(c[n], preamble_symbol(n % kPreamblePeriodSymbols)) << n;
  }
  for (std::size_t n = 0; n < kSyncSymbols; ++n) {
    EXPECT_EQ(c[kPreambleSymbols + n], sync_symbol(n)) << n;
  }
  // The header follows, whitened: de-whiten its first octet (src = 1).
  Whitener w;
  std::uint8_t first = 0;
  for (unsigned i = 0; i < 8; ++i) {
    first = static_cast<std::uint8_t>(first | ((c[kHeaderStartSymbol + i] < 0 ? 1U : 0U) << i));
  }
  EXPECT_EQ(first ^ w.next(), 1);
  EXPECT_EQ(a[frame_symbol_count(3)], 0) << "wrote past the frame";
}

TEST(FastGmskFrameFormat, WhiteningBreaksUpRunsOfEqualPayloadBits) {
  // A payload of zeros would be a pure tone without whitening; after it, the
  // longest run of equal frequency symbols stays short.
  const std::vector<std::uint8_t> zeros(200, 0);
  std::vector<std::int8_t> a(frame_symbol_count(zeros.size()));
  build_frame_symbols(FrameTag{}, zeros, a);
  std::size_t run = 1;
  std::size_t longest = 1;
  for (std::size_t n = kHeaderStartSymbol + 1; n + kTailSymbols < a.size(); ++n) {
    run = a[n] == a[n - 1] ? run + 1 : 1;
    longest = std::max(longest, run);
  }
  EXPECT_LE(longest, 12U);
}

TEST(FastGmskFrameFormat, SyncWordDiffersFromEveryShiftOfThePreamble) {
  std::set<std::uint32_t> seen;
  for (std::size_t shift = 0; shift < kPreamblePeriodSymbols; ++shift) {
    int agree = 0;
    for (std::size_t i = 0; i < kSyncSymbols; ++i) {
      agree += sync_symbol(i) == preamble_symbol((i + shift) % kPreamblePeriodSymbols) ? 1 : 0;
    }
    EXPECT_GT(agree, 8);
    EXPECT_LT(agree, 24);
  }
}

}  // namespace
}  // namespace rfsitl::phy::gmsk
