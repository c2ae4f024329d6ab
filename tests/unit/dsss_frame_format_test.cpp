#include "phy/dsss/frame_format.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "phy/dsss/crc.hpp"
#include "phy/dsss/differential_psk.hpp"

namespace rfsitl::phy::dsss {
namespace {

std::vector<std::uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

TEST(DsssFrameFormat, CrcsMatchTheirCheckValues) {
  EXPECT_EQ(crc16(bytes_of("123456789")), 0x29B1);
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926U);
}

TEST(DsssFrameFormat, HeaderRoundTripsEveryField) {
  const FrameHeader h{Modulation::kDqpsk, 1234, 7, 255, 0xDEADBEEF, 0xA5C3};
  const auto decoded = decode_header(encode_header(h));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->modulation, Modulation::kDqpsk);
  EXPECT_EQ(decoded->length, 1234);
  EXPECT_EQ(decoded->src, 7);
  EXPECT_EQ(decoded->dst, 255);
  EXPECT_EQ(decoded->serial, 0xDEADBEEFU);
  EXPECT_EQ(decoded->control, 0xA5C3);
}

TEST(DsssFrameFormat, HeaderWithAnyFlippedBitIsRejected) {
  const auto good = encode_header(FrameHeader{Modulation::kDbpsk, 80, 1, 2, 42, 0});
  for (std::size_t bit = 0; bit < kHeaderBits; ++bit) {
    auto bad = good;
    bad[bit / 8] = static_cast<std::uint8_t>(bad[bit / 8] ^ (1U << (bit % 8)));
    EXPECT_FALSE(decode_header(bad).has_value()) << "bit " << bit;
  }
}

TEST(DsssFrameFormat, ControlFieldRoundTrips) {
  for (const ControlField f : {ControlField{}, ControlField{true, 0, 0},
                               ControlField{true, 1023, 15}, ControlField{true, 129, 7}}) {
    const auto back = decode_control(encode_control(f));
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(*back, f);
  }
  EXPECT_EQ(encode_control(ControlField{}), 0);
}

TEST(DsssFrameFormat, ControlFieldRejectsWhatItCannotCarry) {
  EXPECT_THROW(encode_control(ControlField{true, 1024, 0}), std::invalid_argument);
  EXPECT_THROW(encode_control(ControlField{true, 0, 16}), std::invalid_argument);
  EXPECT_THROW(encode_control(ControlField{false, 3, 0}), std::invalid_argument);
  EXPECT_FALSE(decode_control(0x4000).has_value());  // reserved bit
  EXPECT_FALSE(decode_control(0x0001).has_value());  // index without a request
}

TEST(DsssFrameFormat, PayloadCrcDetectsCorruption) {
  std::vector<std::uint8_t> body;
  append_payload_with_crc(bytes_of("hello, swarm"), body);
  EXPECT_TRUE(payload_crc_valid(body));
  body[3] ^= 0x10;
  EXPECT_FALSE(payload_crc_valid(body));
  EXPECT_FALSE(payload_crc_valid(std::vector<std::uint8_t>{1, 2, 3}));
}

TEST(DsssFrameFormat, SymbolCountCoversSyncHeaderAndPayload) {
  EXPECT_EQ(frame_symbol_count(Modulation::kDbpsk, 80), 32 + 16 + 104 + 8 * 84);
  EXPECT_EQ(frame_symbol_count(Modulation::kDqpsk, 80), 32 + 16 + 104 + 4 * 84);
  const std::vector<std::uint8_t> payload(80, 0x33);
  for (const Modulation m : {Modulation::kDbpsk, Modulation::kDqpsk}) {
    const FrameHeader h{m, 80, 1, 2, 3, 0};
    EXPECT_EQ(frame_symbols(h, payload).size(), frame_symbol_count(m, 80));
  }
}

TEST(DsssFrameFormat, SfdDoesNotOccurBeforeItsPlace) {
  // Decode the sync part differentially, as the receiver does, and slide the
  // SFD register over it: the only match must be at the SFD's last bit.
  const std::vector<std::uint8_t> payload(4, 0);
  const auto symbols = frame_symbols(FrameHeader{Modulation::kDbpsk, 4, 1, 2, 3, 0}, payload);
  std::uint16_t reg = 0;
  for (std::size_t k = 1; k < kSyncSymbols; ++k) {
    const std::uint8_t bit = dbpsk_decide(symbols[k] * std::conj(symbols[k - 1]));
    reg = static_cast<std::uint16_t>((reg >> 1) | (bit << 15));
    if (k >= kSfdBits) {
      EXPECT_EQ(reg == kSfd, k == kSyncSymbols - 1) << "symbol " << k;
    }
  }
}

}  // namespace
}  // namespace rfsitl::phy::dsss
