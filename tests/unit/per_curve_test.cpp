/// The declared PER curves (phy/per_curve.hpp): every built-in PHY declares
/// one, and each behaves as a packet error rate in AWGN must.
#include "rfsitl/phy/per_curve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::phy {
namespace {

TEST(PerCurve, EveryBuiltInPhyDeclaresOneAndTheExternalOneNone) {
  for (const PhyComponent& p : phy_components()) {
    const PerCurve curve = declared_per_curve(p.info.name, p.info.defaults());
    EXPECT_EQ(static_cast<bool>(curve), p.kind == TransceiverKind::kBuiltIn) << p.info.name;
  }
  EXPECT_THROW(declared_per_curve("no-such-phy", {}), std::invalid_argument);
}

TEST(PerCurve, MonotoneFromOneAtLowSnrToZeroAtHighSnrAndWorseForLongerFrames) {
  for (const PhyComponent& p : phy_components()) {
    if (p.kind != TransceiverKind::kBuiltIn) continue;
    const PerCurve curve = declared_per_curve(p.info.name, p.info.defaults());
    const double sens = make_transceiver(p.info.name)->sensitivity_snr_db();
    SCOPED_TRACE(p.info.name + " (sensitivity " + std::to_string(sens) + " dB)");
    // 30 dB either side of the sensitivity: far below, far above any waterfall.
    EXPECT_GT(curve(sens - 30.0, 80), 0.999);
    EXPECT_LT(curve(sens + 30.0, 80), 1e-6);
    EXPECT_EQ(curve(NAN, 80), 1.0);
    double previous = 1.0;
    for (double snr = sens - 30.0; snr <= sens + 30.0; snr += 0.05) {
      const double per = curve(snr, 80);
      ASSERT_GE(per, 0.0) << snr;
      ASSERT_LE(per, previous + 1e-12) << "rises at " << snr << " dB";
      previous = per;
      // Where neither saturates, more bits mean more chances of an error.
      if (per > 1e-6 && per < 0.999) {
        EXPECT_GT(curve(snr, 1000), per) << snr;
        EXPECT_LT(curve(snr, 10), per) << snr;
      }
    }
    // The sensitivity is where a PHY "decodes reliably": its own curve says
    // at most a few tens of percent are lost there (80-byte frames), and the
    // waterfall lies within 6 dB of it.
    EXPECT_LT(curve(sens, 80), 0.35);
    EXPECT_GT(curve(sens - 6.0, 80), 0.5);
  }
}

TEST(PerCurve, EveryOfdmRateLosesAboutTenPercentAtItsSensitivity) {
  // sensitivity_snr_db() is where 80-byte frames reach 10 % PER (measured);
  // each rate's declared waterfall must say about that there.
  const PhyComponent* ofdm = find_phy("ofdm");
  ASSERT_NE(ofdm, nullptr);
  for (const int rate : {6, 9, 12, 18, 24, 36, 48, 54}) {
    config::Settings s = ofdm->info.defaults();
    s.set("rate_mbps", static_cast<std::uint64_t>(rate));
    const double sens = make_transceiver("ofdm", s)->sensitivity_snr_db();
    const double per = declared_per_curve("ofdm", s)(sens, 80);
    EXPECT_GT(per, 0.03) << rate << " Mbit/s";
    EXPECT_LT(per, 0.3) << rate << " Mbit/s";
  }
}

TEST(PerCurve, BitErrorHelpersMatchTheirClosedForms) {
  EXPECT_NEAR(q_function(0.0), 0.5, 1e-15);
  EXPECT_NEAR(q_function(3.090232), 1e-3, 1e-8);
  // 1 - (1 - p)^n for a p where 1 - p rounds: the log form keeps it.
  EXPECT_NEAR(per_of_bits(1e-17, 1e6), 1e-11, 1e-15);
  EXPECT_NEAR(per_of_bits(0.01, 100), 1.0 - std::pow(0.99, 100), 1e-12);
}

}  // namespace
}  // namespace rfsitl::phy
