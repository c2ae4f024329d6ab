// The seam for the cognitive code adaptation: per-frame TX code, listening on
// several codes at once, and the control field in every header.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "phy/dsss/dsss_transceiver.hpp"
#include "phy/dsss/frame_format.hpp"

namespace rfsitl::phy {
namespace {

struct Decode {
  FrameTag tag;
  bool payload_valid = false;
  std::size_t code = 0;
  std::uint16_t control = 0;
};

/// Collects decodes together with what the radio's last_rx_info() said.
class Collector final : public RxHandler {
 public:
  explicit Collector(const DsssTransceiver& radio) : radio_(radio) {}
  void on_rx(const RxEvent& ev) override {
    const DsssRxInfo& info = radio_.last_rx_info();
    decodes.push_back({ev.tag, ev.payload_valid, info.code, info.control});
  }
  std::vector<Decode> valid() const {
    std::vector<Decode> v;
    std::copy_if(decodes.begin(), decodes.end(), std::back_inserter(v),
                 [](const Decode& d) { return d.payload_valid; });
    return v;
  }
  std::vector<Decode> decodes;

 private:
  const DsssTransceiver& radio_;
};

std::unique_ptr<DsssTransceiver> radio(const std::string& code) {
  DsssSettings s;
  s.code = code;
  return make_code_agile_dsss_transceiver(s);
}

std::vector<cf32> transmit_frame(Transceiver& tx, const FrameTag& tag) {
  const std::vector<std::uint8_t> payload(24, static_cast<std::uint8_t>(tag.serial));
  std::vector<cf32> out(tx.start_frame(tag, payload));
  tx.transmit(out);
  return out;
}

/// Frames with gaps, random phase per frame, AWGN at 10 dB per-sample SNR.
std::vector<cf32> over_the_air(const std::vector<std::vector<cf32>>& frames, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0.0F, 6.2831853F);
  std::normal_distribution<float> g(0.0F, static_cast<float>(std::sqrt(0.05)));
  std::vector<cf32> x(600);
  for (const auto& f : frames) {
    const cf32 c = std::polar(1.0F, phase(rng));
    for (const cf32& s : f) x.push_back(c * s);
    x.resize(x.size() + 600);
  }
  for (cf32& s : x) s += cf32{g(rng), g(rng)};
  return x;
}

void feed(Transceiver& rx, std::span<const cf32> x, RxHandler& h) {
  for (std::size_t i = 0; i < x.size(); i += 250)
    rx.receive(x.subspan(i, std::min<std::size_t>(250, x.size() - i)), h);
}

TEST(DsssCodeAgility, FrameOnCodeAIsDecodedOnlyWhenTheReceiverListensOnA) {
  auto tx = radio("gold127:1");
  auto rx = radio("gold127:2");
  const auto x =
      over_the_air({transmit_frame(*tx, {1, 2, 10}), transmit_frame(*tx, {1, 2, 11})}, 1);
  Collector only_b(*rx);
  feed(*rx, x, only_b);
  EXPECT_TRUE(only_b.valid().empty()) << "decoded on the wrong code";

  const std::size_t a = rx->add_code("gold127:1");
  const std::vector<std::size_t> both = {0, a};
  rx->set_listen_codes(both);
  Collector listening_both(*rx);
  feed(*rx, x, listening_both);
  const auto got = listening_both.valid();
  ASSERT_EQ(got.size(), 2U);
  for (const Decode& d : got) EXPECT_EQ(d.code, a) << "reported the code it arrived on";
}

TEST(DsssCodeAgility, ListensOnTwoCodesAtOnceAndSaysWhichOneCarriedEachFrame) {
  auto tx = radio("gold127:3");
  auto rx = radio("gold127:3");
  const std::size_t tx_mine = tx->add_code("gold127:60");
  const std::size_t rx_mine = rx->add_code("gold127:60");
  const std::vector<std::size_t> listen = {0, rx_mine};
  rx->set_listen_codes(listen);
  std::vector<std::vector<cf32>> frames;
  for (std::uint32_t k = 0; k < 4; ++k) {
    tx->set_tx_code(2, k % 2 == 0 ? 0 : tx_mine);
    frames.push_back(transmit_frame(*tx, {1, 2, k}));
  }
  Collector c(*rx);
  feed(*rx, over_the_air(frames, 2), c);
  const auto got = c.valid();
  ASSERT_EQ(got.size(), 4U);
  for (const Decode& d : got) {
    EXPECT_EQ(d.code, d.tag.serial % 2 == 0 ? 0U : rx_mine) << "frame " << d.tag.serial;
  }
}

TEST(DsssCodeAgility, DecodesAWeakFrameOnOneCodeUnderAContinuousStreamOnTheOther) {
  // Each listened code has its own search and demodulator: a peer that never
  // stops sending on the common code (6 dB stronger) neither hides nor blocks
  // the frames sent on the node's own code.
  auto loud = radio("gold127:3");
  auto quiet = radio("gold127:3");
  auto rx = radio("gold127:3");
  quiet->set_tx_code(2, quiet->add_code("gold127:60"));
  const std::size_t mine = rx->add_code("gold127:60");
  const std::vector<std::size_t> listen = {0, mine};
  rx->set_listen_codes(listen);
  const std::size_t len = loud->frame_samples(24);
  std::vector<cf32> x(5 * len);
  for (std::uint32_t k = 0; (k + 1) * len <= x.size(); ++k) {
    const auto f = transmit_frame(*loud, {5, 9, 100 + k});
    for (std::size_t i = 0; i < len; ++i) x[k * len + i] += f[i];
  }
  const cf32 weak = std::polar(0.5F, 1.0F);  // -6 dB, another phase
  for (std::uint32_t k = 0; k < 3; ++k) {
    const auto f = transmit_frame(*quiet, {1, 2, k});
    const std::size_t start = len / 3 + k * (len + 333);
    for (std::size_t i = 0; i < len; ++i) x[start + i] += weak * f[i];
  }
  std::mt19937 rng(8);
  std::normal_distribution<float> g(0.0F, 0.2F);  // ~ -11 dB below the weak one
  for (cf32& v : x) v += cf32{g(rng), g(rng)};
  Collector c(*rx);
  feed(*rx, x, c);
  std::vector<std::uint32_t> weak_frames;
  std::size_t loud_frames = 0;
  for (const Decode& d : c.valid()) {
    if (d.tag.serial >= 100) {
      ++loud_frames;
      EXPECT_EQ(d.code, 0U);
    } else {
      weak_frames.push_back(d.tag.serial);
      EXPECT_EQ(d.code, mine);
    }
  }
  EXPECT_EQ(weak_frames, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(loud_frames, 5U);
}

TEST(DsssCodeAgility, PerDestinationTableChoosesEachFramesCode) {
  auto tx = radio("gold127:0");
  const std::size_t special = tx->add_code("gold127:9");
  tx->set_tx_code(3, special);
  EXPECT_EQ(tx->tx_code(3), special);
  EXPECT_EQ(tx->tx_code(2), 0U) << "unlisted destinations use the default code";
  EXPECT_EQ(tx->tx_code(kBroadcastId), 0U);
  const auto x = over_the_air({transmit_frame(*tx, {1, 2, 20}), transmit_frame(*tx, {1, 3, 30}),
                               transmit_frame(*tx, {1, kBroadcastId, 40})},
                              3);
  auto default_only = radio("gold127:0");
  Collector c(*default_only);
  feed(*default_only, x, c);
  const auto got = c.valid();
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].tag.serial, 20U);
  EXPECT_EQ(got[1].tag.serial, 40U);

  auto special_only = radio("gold127:9");
  Collector s(*special_only);
  feed(*special_only, x, s);
  ASSERT_EQ(s.valid().size(), 1U);
  EXPECT_EQ(s.valid()[0].tag.serial, 30U);
}

TEST(DsssCodeAgility, ControlFieldTravelsInEveryHeader) {
  auto tx = radio("mseq31");
  auto rx = radio("mseq31");
  const dsss::ControlField request{true, 77, 5};
  std::vector<std::vector<cf32>> frames;
  frames.push_back(transmit_frame(*tx, {1, 2, 1}));  // before any request: 0
  tx->set_tx_control(dsss::encode_control(request));
  frames.push_back(transmit_frame(*tx, {1, 2, 2}));
  frames.push_back(transmit_frame(*tx, {1, 2, 3}));  // repeated while unchanged
  Collector c(*rx);
  feed(*rx, over_the_air(frames, 4), c);
  const auto got = c.valid();
  ASSERT_EQ(got.size(), 3U);
  EXPECT_EQ(got[0].control, 0);
  for (std::size_t k = 1; k < 3; ++k) {
    const auto decoded = dsss::decode_control(got[k].control);
    ASSERT_TRUE(decoded.has_value());
    EXPECT_EQ(*decoded, request);
  }
}

TEST(DsssCodeAgility, ListeningChangeWaitsForTheFrameInProgress) {
  auto tx = radio("gold31:4");
  auto rx = radio("gold31:4");
  const std::size_t other_tx = tx->add_code("gold31:20");
  const std::size_t other_rx = rx->add_code("gold31:20");
  const auto first = transmit_frame(*tx, {1, 2, 1});   // default code
  const auto second = transmit_frame(*tx, {1, 2, 2});  // default code, after the switch
  tx->set_tx_code(2, other_tx);
  const auto third = transmit_frame(*tx, {1, 2, 3});  // the new code
  const auto x = over_the_air({first, second, third}, 5);
  Collector c(*rx);
  // Switch listening to the other code half way through the first frame.
  const std::size_t half = 600 + first.size() / 2;
  feed(*rx, std::span(x).first(half), c);
  ASSERT_TRUE(rx->rx_busy());
  const std::vector<std::size_t> listen = {other_rx};
  rx->set_listen_codes(listen);
  feed(*rx, std::span(x).subspan(half), c);
  const auto got = c.valid();
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].tag.serial, 1U) << "the frame in progress finished on the old code";
  EXPECT_EQ(got[0].code, 0U);
  EXPECT_EQ(got[1].tag.serial, 3U) << "afterwards only the new code is heard";
  EXPECT_EQ(got[1].code, other_rx);
}

TEST(DsssCodeAgility, CodeBookAcceptsOnlyCodesOfTheDefaultLength) {
  auto r = radio("gold127");
  EXPECT_EQ(r->code_name(0), "gold127:0");
  EXPECT_EQ(r->add_code("mseq127"), 1U);
  EXPECT_EQ(r->add_code("gold127:0"), 0U) << "an existing code keeps its index";
  EXPECT_EQ(r->code_count(), 2U);
  EXPECT_THROW(r->add_code("gold63"), std::invalid_argument);
  EXPECT_THROW(r->add_code("walsh"), std::invalid_argument);
}

TEST(DsssCodeAgility, BadIndicesAndListeningSetsThrow) {
  auto r = radio("mseq31");
  r->add_code("gold31:1");
  EXPECT_THROW(r->set_tx_code(2, 2), std::out_of_range);
  const std::vector<std::size_t> none;
  EXPECT_THROW(r->set_listen_codes(none), std::invalid_argument);
  const std::vector<std::size_t> five = {0, 1, 0, 1, 0};
  EXPECT_THROW(r->set_listen_codes(five), std::invalid_argument);
  const std::vector<std::size_t> bad = {0, 3};
  EXPECT_THROW(r->set_listen_codes(bad), std::out_of_range);
}

}  // namespace
}  // namespace rfsitl::phy
