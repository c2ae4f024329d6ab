// Cognitive code adaptation: the SINR-maximizing code choice (code_adaptation.hpp)
// and the control-field protocol of the adaptive DSSS transceiver.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "phy/dsss/code_adaptation.hpp"
#include "phy/dsss/codes.hpp"
#include "phy/dsss/dsss_transceiver.hpp"

namespace rfsitl::phy {
namespace {

using dsss::Chip;

/// Output SINR of despreading with `s`, measured by brute force: the mean power
/// of sum_i s[i] w[n + i] over every window start n of an interference record,
/// against L^2 for a unit-power wanted chip stream. Independent of the lag model.
double measured_sinr_db(const std::vector<Chip>& s, const std::vector<cf32>& w) {
  const std::size_t l = s.size();
  double power = 0.0;
  std::size_t count = 0;
  for (std::size_t n = 0; n + l <= w.size(); ++n) {
    cf32 y{};
    for (std::size_t i = 0; i < l; ++i) y += static_cast<float>(s[i]) * w[n + i];
    power += static_cast<double>(std::norm(y));
    ++count;
  }
  const double ll = static_cast<double>(l);
  return 10.0 * std::log10(ll * ll / (power / static_cast<double>(count)));
}

std::vector<cf32> white_noise(std::size_t n, float power, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0F, std::sqrt(power / 2.0F));
  std::vector<cf32> x(n);
  for (cf32& v : x) v = cf32{g(rng), g(rng)};
  return x;
}

dsss::CodeSelector selector_for(const std::string& code) {
  std::vector<std::vector<Chip>> chips;
  for (const auto& c : dsss::adaptation_candidates(dsss::code_by_name(code), 1024)) {
    chips.push_back(c.chips);
  }
  return dsss::CodeSelector(std::move(chips));
}

/// A continuous DSSS transmitter on `code`: back-to-back frames of random data.
std::vector<cf32> dsss_stream(const std::string& code, std::size_t n, float amplitude,
                              std::uint32_t seed) {
  DsssSettings s;
  s.code = code;
  auto jam = make_code_agile_dsss_transceiver(s);
  std::mt19937 rng(seed);
  std::vector<cf32> x;
  std::uint32_t serial = 0;
  while (x.size() < n) {
    std::vector<std::uint8_t> payload(40);
    for (auto& b : payload) b = static_cast<std::uint8_t>(rng());
    std::vector<cf32> f(jam->start_frame({5, 9, serial++}, payload));
    jam->transmit(f);
    for (const cf32& v : f) x.push_back(amplitude * v);
  }
  x.resize(n);
  return x;
}

TEST(DsssAdaptationStep, LagAccumulatorFedInPiecesEqualsOneRecord) {
  const auto x = white_noise(3000, 1.0F, 1);
  const auto whole = dsss::estimate_lags(x, 31, 3);
  dsss::LagAccumulator acc(31, 3);
  for (std::size_t i = 0; i < x.size(); i += 77) {
    acc.push(std::span(x).subspan(i, std::min<std::size_t>(77, x.size() - i)));
  }
  const auto pieces = dsss::normalized_lags(acc.sums());
  ASSERT_EQ(pieces.size(), whole.size());
  for (std::size_t k = 0; k < whole.size(); ++k) {
    EXPECT_NEAR(std::abs(pieces[k] - whole[k]), 0.0, 1e-5) << "lag " << k;
  }
  EXPECT_NEAR(whole[0].real(), 1.0, 0.1);
}

TEST(DsssAdaptationStep, PredictedSinrMatchesBruteForceDespreading) {
  // The Toeplitz quadratic form equals what a despreader measures.
  const auto sel = selector_for("gold31:0");
  auto w = white_noise(40000, 0.5F, 2);
  for (std::size_t n = 0; n < w.size(); ++n) {
    w[n] += 2.0F * std::polar(1.0F, 0.7F * static_cast<float>(n));
  }
  const auto lags = dsss::estimate_lags(w, 31);
  for (std::size_t i : {0U, 5U, 17U}) {
    EXPECT_NEAR(sel.sinr_db(i, lags), measured_sinr_db(sel.code(i), w), 0.2) << "candidate " << i;
  }
}

TEST(DsssAdaptationStep, ChoosesACodeWithMeasurablyHigherSinrUnderANarrowbandTone) {
  const auto sel = selector_for("gold127:0");
  const auto tone = [](std::size_t n, std::uint32_t seed) {
    auto w = white_noise(n, 0.1F, seed);
    for (std::size_t k = 0; k < n; ++k) {
      w[k] += 3.0F * std::polar(1.0F, 0.9F + 0.37F * static_cast<float>(k));  // 10 dB tone
    }
    return w;
  };
  const auto lags = dsss::estimate_lags(tone(30000, 3), 127, 7);
  const auto choice = sel.choose(lags, 0, 1.0);
  ASSERT_NE(choice.index, 0U);
  // Measured on a fresh record, independently of the estimate.
  const auto fresh = tone(20000, 4);
  const double fixed_db = measured_sinr_db(sel.code(0), fresh);
  const double chosen_db = measured_sinr_db(sel.code(choice.index), fresh);
  std::printf("tone: fixed code %.1f dB, chosen %zu %.1f dB\n", fixed_db, choice.index, chosen_db);
  EXPECT_GT(chosen_db, fixed_db + 3.0);
}

TEST(DsssAdaptationStep, ChoosesACodeWithHigherSinrUnderAContinuousTransmitterOnTheDefaultCode) {
  const auto sel = selector_for("gold127:0");
  const auto jammed = [](std::size_t n, std::uint32_t seed) {
    auto w = white_noise(n, 0.05F, seed);
    const auto j = dsss_stream("gold127:0", n + 5000, 2.0F, seed + 100);
    for (std::size_t k = 0; k < n; ++k) w[k] += j[k + 1234];
    return w;
  };
  const auto lags = dsss::estimate_lags(jammed(120000, 5), 127, 7);
  const auto choice = sel.choose(lags, 0, 1.0);
  ASSERT_NE(choice.index, 0U);
  const auto fresh = jammed(60000, 6);
  const double fixed_db = measured_sinr_db(sel.code(0), fresh);
  const double chosen_db = measured_sinr_db(sel.code(choice.index), fresh);
  std::printf("co-code interferer: fixed %.2f dB, chosen %zu %.2f dB (predicted %.2f -> %.2f)\n",
              fixed_db, choice.index, chosen_db, choice.current_sinr_db, choice.sinr_db);
  EXPECT_GT(chosen_db, fixed_db + 1.0);
}

TEST(DsssAdaptationStep, KeepsTheFixedCodeUnderWhiteNoise) {
  for (const char* code : {"gold31:0", "gold127:0"}) {
    const auto sel = selector_for(code);
    const std::size_t l = sel.length();
    const std::size_t stride = std::max<std::size_t>(1, l / 16);
    // The transceiver's default amount: 8192 windows.
    const auto lags = dsss::estimate_lags(white_noise(8192 * stride + l, 1.0F, 7), l, stride);
    const auto choice = sel.choose(lags, 0, 1.0);
    EXPECT_EQ(choice.index, 0U) << code;
    double best = -1e9;
    for (std::size_t i = 0; i < sel.size(); ++i) best = std::max(best, sel.sinr_db(i, lags));
    EXPECT_LT(best - choice.current_sinr_db, 0.6) << code << ": no code is much better";
  }
}

TEST(DsssAdaptationStep, CandidateListIsTheDefaultThenItsGoldFamily) {
  const auto gold = dsss::adaptation_candidates(dsss::code_by_name("gold31:4"), 1024);
  ASSERT_EQ(gold.size(), 33U);
  EXPECT_EQ(gold[0].name, "gold31:4");
  EXPECT_EQ(gold[1].name, "gold31:0");
  std::set<std::vector<Chip>> distinct;
  for (const auto& c : gold) distinct.insert(c.chips);
  EXPECT_EQ(distinct.size(), 33U);
  EXPECT_EQ(dsss::adaptation_candidates(dsss::code_by_name("gold127"), 10).size(), 10U);
  EXPECT_EQ(dsss::adaptation_candidates(dsss::code_by_name("barker11"), 10).size(), 1U);
  const auto m = dsss::adaptation_candidates(dsss::code_by_name("mseq63"), 1024);
  EXPECT_EQ(m.size(), 65U) << "mseq63 is a member of the gold63 family";
}

// ---- the protocol, two transceivers driven in the test ----

constexpr NodeId kA = 1;  // sends data to B
constexpr NodeId kB = 2;  // the jammed receiver; its frames to A carry its request

class Counter final : public RxHandler {
 public:
  explicit Counter(NodeId src) : src_(src) {}
  void on_rx(const RxEvent& ev) override {
    if (ev.payload_valid && ev.tag.src == src_) serials.insert(ev.tag.serial);
  }
  std::set<std::uint32_t> serials;

 private:
  NodeId src_;
};

struct LinkResult {
  std::size_t sent = 0;
  std::size_t delivered = 0;
  std::size_t sent_after_switch = 0;  // A's frames started after A switched its code to B
  std::size_t delivered_after_switch = 0;
  std::size_t b_switches = 0;
  std::size_t a_code_to_b = 0;
  std::size_t b_preferred = 0;
  std::vector<std::size_t> b_listen;
  bool dropped_an_update = false;
  double pdr() const {
    return sent ? static_cast<double>(delivered) / static_cast<double>(sent) : 0;
  }
  double pdr_after() const {
    return sent_after_switch ? static_cast<double>(delivered_after_switch) /
                                   static_cast<double>(sent_after_switch)
                             : 0;
  }
};

/// A sends `frames` frames to B, B one to A after each; a continuous transmitter
/// on the default code, 3 dB above A's signal, reaches B only. If
/// `drop_first_update`, the first frame B sends after changing its code (the one
/// carrying the new request) never reaches A.
LinkResult run_link(bool adaptive, std::size_t frames, bool drop_first_update) {
  DsssSettings s;
  s.code = "gold31:0";
  s.max_payload_bytes = 32;
  s.adaptive = adaptive;
  auto a = make_code_agile_dsss_transceiver(s);
  auto b = make_code_agile_dsss_transceiver(s);
  s.adaptive = false;
  s.max_payload_bytes = 64;
  auto jam = make_code_agile_dsss_transceiver(s);

  const std::size_t tick = 250;
  const std::size_t frame_len = a->frame_samples(24);
  // A's frame, then B's, each in a slot of whole ticks.
  const std::size_t slot = (frame_len + 1500 + tick - 1) / tick * tick;
  const std::size_t total = 2 * slot * frames + 4 * tick;
  std::mt19937 rng(11);
  std::normal_distribution<float> g(0.0F, std::sqrt(0.02F / 2.0F));  // 17 dB below A
  const cf32 gain_ab = std::polar(1.0F, 0.4F);
  const cf32 gain_jb = std::polar(std::sqrt(2.0F), 2.1F);
  const cf32 gain_ba = std::polar(1.0F, -1.3F);

  Counter at_b(kA);
  Counter at_a(kB);
  LinkResult r;
  std::vector<std::uint32_t> after_switch;
  std::vector<cf32> xa(tick), xb(tick), xj(tick), in(tick);
  bool a_was_tx = false;
  bool b_was_tx = false;
  bool drop_b_frame = false;
  std::uint32_t jam_serial = 0;
  for (std::size_t t = 0; t < total; t += tick) {
    const std::size_t k = t / (2 * slot);
    const std::size_t phase = t % (2 * slot);
    const std::vector<std::uint8_t> payload(24, static_cast<std::uint8_t>(k));
    if (phase == 0 && k < frames && !a->tx_busy()) {
      a->start_frame({kA, kB, static_cast<std::uint32_t>(k)}, payload);
      ++r.sent;
      if (adaptive && a->tx_code(kB) != 0) after_switch.push_back(static_cast<std::uint32_t>(k));
    }
    if (phase == slot && k < frames && !b->tx_busy()) {
      const bool carries_update = b->adaptation_status().switches > 0;
      drop_b_frame = drop_first_update && carries_update && !r.dropped_an_update;
      if (drop_b_frame) r.dropped_an_update = true;
      b->start_frame({kB, kA, static_cast<std::uint32_t>(k)}, payload);
    }
    if (!jam->tx_busy()) {
      std::vector<std::uint8_t> junk(60, static_cast<std::uint8_t>(jam_serial));
      jam->start_frame({5, 9, jam_serial++}, junk);
    }
    const bool a_tx = a->transmit(xa) > 0;
    const bool b_tx = b->transmit(xb) > 0;
    jam->transmit(xj);
    if (!b_tx) {
      if (b_was_tx) b->reset_receiver();
      for (std::size_t i = 0; i < tick; ++i) {
        in[i] = gain_ab * xa[i] + gain_jb * xj[i] + cf32{g(rng), g(rng)};
      }
      b->receive(in, at_b);
    }
    if (!a_tx) {
      if (a_was_tx) a->reset_receiver();
      const cf32 ba = drop_b_frame ? cf32{} : gain_ba;
      for (std::size_t i = 0; i < tick; ++i) in[i] = ba * xb[i] + cf32{g(rng), g(rng)};
      a->receive(in, at_a);
    }
    a_was_tx = a_tx;
    b_was_tx = b_tx;
  }
  r.delivered = at_b.serials.size();
  r.sent_after_switch = after_switch.size();
  for (std::uint32_t k : after_switch) r.delivered_after_switch += at_b.serials.count(k);
  r.b_switches = b->adaptation_status().switches;
  r.b_preferred = b->adaptation_status().preferred;
  r.a_code_to_b = a->tx_code(kB);
  r.b_listen = b->listen_codes();
  return r;
}

TEST(DsssAdaptationLink, FixedCodeLosesMostFramesAndAdaptiveLinkDeliversMostAfterTheSwitch) {
  const LinkResult fixed = run_link(false, 24, false);
  const LinkResult adaptive = run_link(true, 24, false);
  std::printf(
      "PDR A->B under a default-code interferer: fixed %zu/%zu = %.2f; adaptive %zu/%zu "
      "= %.2f overall, %zu/%zu = %.2f after the switch (B switched %zu times)\n",
      fixed.delivered, fixed.sent, fixed.pdr(), adaptive.delivered, adaptive.sent, adaptive.pdr(),
      adaptive.delivered_after_switch, adaptive.sent_after_switch, adaptive.pdr_after(),
      adaptive.b_switches);
  EXPECT_LT(fixed.pdr(), 0.3) << "the interferer must hurt the fixed-code link";
  ASSERT_GE(adaptive.b_switches, 1U);
  EXPECT_EQ(adaptive.a_code_to_b, adaptive.b_preferred) << "A sends on the code B asked for";
  EXPECT_EQ(adaptive.b_listen, (std::vector<std::size_t>{0, adaptive.b_preferred}))
      << "B stopped listening on the old code once A's frames came on the new one";
  EXPECT_GE(adaptive.sent_after_switch, 12U) << "the switch came early enough";
  EXPECT_GT(adaptive.pdr_after(), 0.8);
  EXPECT_GT(adaptive.pdr(), fixed.pdr() + 0.3);
}

TEST(DsssAdaptationLink, LostFrameCarryingTheUpdateDoesNotBreakTheLink) {
  const LinkResult r = run_link(true, 24, true);
  std::printf("with the first update dropped: %zu/%zu after the switch\n", r.delivered_after_switch,
              r.sent_after_switch);
  ASSERT_TRUE(r.dropped_an_update);
  EXPECT_EQ(r.a_code_to_b, r.b_preferred) << "the repeated request got through";
  EXPECT_LT(r.pdr(), 1.0) << "frames were lost before the switch";
  EXPECT_GE(r.sent_after_switch, 10U);
  EXPECT_GT(r.pdr_after(), 0.8);
}

TEST(DsssAdaptationLink, WithoutInterferenceTheAdaptiveLinkKeepsTheDefaultCode) {
  // No interferer: same harness with the jammer silenced is not available, so
  // check the transceiver's own decision directly on noise.
  DsssSettings s;
  s.code = "gold31:0";
  s.max_payload_bytes = 32;
  s.adaptive = true;
  auto b = make_code_agile_dsss_transceiver(s);
  Counter none(kA);
  const auto noise = white_noise(200000, 1.0F, 9);
  for (std::size_t i = 0; i < noise.size(); i += 250) {
    b->receive(std::span(noise).subspan(i, 250), none);
  }
  EXPECT_GE(b->adaptation_status().decisions, 3U);
  EXPECT_EQ(b->adaptation_status().switches, 0U);
  EXPECT_EQ(b->listen_codes(), (std::vector<std::size_t>{0}));
}

TEST(DsssAdaptationLink, AdaptiveRadioHoldsTheSharedCandidateListInItsBook) {
  DsssSettings s;
  s.code = "gold31:0";
  s.adaptive = true;
  auto r = make_code_agile_dsss_transceiver(s);
  EXPECT_EQ(r->candidate_count(), 33U);
  EXPECT_EQ(r->candidate_code(0), 0U);
  EXPECT_EQ(r->code_count(), 33U) << "both ends hold the same book";
  s.adaptive = false;
  EXPECT_EQ(make_code_agile_dsss_transceiver(s)->candidate_count(), 1U);
  s.adapt_max_candidates = 0;
  EXPECT_THROW(make_code_agile_dsss_transceiver(s), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy
