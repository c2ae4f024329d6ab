#include "rfsitl/phy/gfsk/gfsk_frame.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <vector>

#include "rfsitl/common/crc.hpp"
#include "rfsitl/phy/gfsk/gfsk_modulator.hpp"
#include "rfsitl/phy/gmsk/frame_format.hpp"

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

TEST(GfskModulator, SpanFollowsTheGaussianWidth) {
  EXPECT_EQ(gaussian_span_symbols(0.0F), 1U);
  EXPECT_EQ(gaussian_span_symbols(1.0F), 2U);
  EXPECT_EQ(gaussian_span_symbols(0.5F), 3U);
  EXPECT_EQ(gaussian_span_symbols(0.3F), 4U);
  EXPECT_EQ(gaussian_span_symbols(0.2F), 5U);
}

TEST(GfskModulator, UnitAmplitudeAndToneOfRunsAndPhaseTurnPerSymbol) {
  for (const float bt : {0.0F, 0.5F, 0.2F}) {
    const unsigned k = 8;
    const float h = 0.7F;
    GfskModulator mod(k, h, bt);
    std::vector<std::int8_t> sym(40, 1);
    for (std::size_t i = 20; i < 40; ++i) sym[i] = -1;
    std::vector<cf32> x(mod.frame_samples(sym.size()));
    ASSERT_EQ(mod.start(sym), x.size());
    ASSERT_EQ(mod.generate(x), x.size());
    EXPECT_EQ(mod.samples_left(), 0U);
    for (const cf32& v : x) EXPECT_NEAR(std::abs(v), 1.0F, 1e-5F);
    // Deep inside each run the frequency is +-fd = +-h / (2k) cycles per sample
    // (to 0.05% at BT = 0.2, where the truncated pulse is renormalised).
    const double fd = 2.0 * std::numbers::pi * h / (2.0 * k);
    for (std::size_t n = 10 * k; n < 14 * k; ++n) {
      EXPECT_NEAR(std::arg(x[n + 1] * std::conj(x[n])), fd, 1e-3) << "bt=" << bt << " n=" << n;
    }
    for (std::size_t n = 30 * k; n < 34 * k; ++n) {
      EXPECT_NEAR(std::arg(x[n + 1] * std::conj(x[n])), -fd, 1e-3) << "bt=" << bt << " n=" << n;
    }
  }
}

TEST(GfskModulator, StreamingInPiecesGivesTheSameSamples) {
  GfskModulator a(5, 1.3F, 0.3F);
  GfskModulator b(5, 1.3F, 0.3F);
  std::vector<std::int8_t> sym{1, -1, -1, 1, 1, 1, -1, 1, -1, -1, 1};
  std::vector<cf32> whole(a.frame_samples(sym.size()));
  a.start(sym);
  a.generate(whole);
  b.start(sym);
  std::vector<cf32> pieces;
  std::vector<cf32> chunk(7, cf32{9.0F, 9.0F});
  while (b.samples_left() > 0) {
    const std::size_t n = b.generate(chunk);
    pieces.insert(pieces.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(n));
  }
  ASSERT_EQ(pieces.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) EXPECT_EQ(pieces[i], whole[i]);
}

}  // namespace
}  // namespace rfsitl::phy::gfsk
