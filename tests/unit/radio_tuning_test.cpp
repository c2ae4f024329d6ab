// Radios on their own frequencies: the spectral masks' integrals, what a link
// between two tunings is (in band, leaking, out of band), and the frequency
// shift on the sample grid.
#include "rfsitl/channel/radio_tuning.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "rfsitl/channel/channel.hpp"
#include "rfsitl/channel/frequency_shift.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::channel {
namespace {

// IEEE 802.11 clause 17's transmit spectrum mask for 20 MHz channels, in MHz
// and dBr, written out here again, integrated by the trapezoid rule on a fine
// grid (not the code's closed form): the independent figure.
double standard_mask_fraction_db(double df_mhz, double rx_width_mhz) {
  const double f[] = {0.0, 9.0, 11.0, 20.0, 30.0};
  const double d[] = {0.0, 0.0, -20.0, -28.0, -40.0};
  const auto density = [&](double x) {
    x = std::abs(x);
    if (x > 30.0) return 0.0;
    int i = 0;
    while (x > f[i + 1]) ++i;
    return std::pow(10.0, (d[i] + (d[i + 1] - d[i]) * (x - f[i]) / (f[i + 1] - f[i])) / 10.0);
  };
  const auto integral = [&](double lo, double hi) {
    constexpr int kSteps = 200000;
    const double h = (hi - lo) / kSteps;
    double sum = 0.5 * (density(lo) + density(hi));
    for (int i = 1; i < kSteps; ++i) sum += density(lo + i * h);
    return sum * h;
  };
  return 10.0 * std::log10(integral(-df_mhz - rx_width_mhz / 2, -df_mhz + rx_width_mhz / 2) /
                           integral(-30.0, 30.0));
}

RadioTuning wifi(double centre_hz, const SpectralMask& mask) {
  RadioTuning t;
  t.tx_hz = t.rx_hz = centre_hz;
  t.bandwidth_hz = 20e6;
  t.mask = mask;
  return t;
}

SpectralMask ofdm_mask() {
  const auto* ofdm = phy::find_phy("ofdm");
  return ofdm->spectral_mask(ofdm->info.defaults());
}

TEST(RadioTuning, AFlatMaskHoldsItsPowerInItsChannel) {
  const std::vector<MaskPoint> flat{{0.0, 0.0}, {0.5, 0.0}};
  EXPECT_NEAR(mask_power_fraction(flat, -0.5, 0.5), 1.0, 1e-12);
  EXPECT_NEAR(mask_power_fraction(flat, 0.0, 0.5), 0.5, 1e-12);
  EXPECT_NEAR(mask_power_fraction(flat, 0.25, 2.0), 0.25, 1e-12);
  EXPECT_EQ(mask_power_fraction(flat, 0.6, 2.0), 0.0);
}

TEST(RadioTuning, TheOfdmMaskLeaksWhatTheStandardsMaskIntegratesTo) {
  const SpectralMask mask = ofdm_mask();
  for (const double df_mhz : {5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0}) {
    const LinkBand b = link_band(wifi(2.412e9 + df_mhz * 1e6, mask), wifi(2.412e9, mask), 20e6);
    ASSERT_EQ(b.relation, BandRelation::kLeaking) << df_mhz;
    EXPECT_DOUBLE_EQ(b.offset_hz, df_mhz * 1e6);
    EXPECT_NEAR(10.0 * std::log10(b.kappa), standard_mask_fraction_db(df_mhz, 20.0), 0.01)
        << df_mhz;
  }
}

TEST(RadioTuning, SameChannelIsInBandAndFarChannelsAreNotHeard) {
  const SpectralMask mask = ofdm_mask();
  const LinkBand same = link_band(wifi(2.437e9, mask), wifi(2.437e9, mask), 20e6);
  EXPECT_EQ(same.relation, BandRelation::kInBand);
  EXPECT_EQ(same.kappa, 1.0F);
  // Channels 1 and 11: 50 MHz apart, beyond the mask's last point.
  const LinkBand far = link_band(wifi(2.462e9, mask), wifi(2.412e9, mask), 20e6);
  EXPECT_EQ(far.relation, BandRelation::kOutOfBand);
  EXPECT_EQ(far.kappa, 0.0F);
}

TEST(RadioTuning, ANarrowSignalInsideAWideReceiverIsInBandAtItsOffset) {
  RadioTuning narrow = wifi(2.4e9 + 3e6, {});
  narrow.bandwidth_hz = 1e6;
  const RadioTuning wide = wifi(2.4e9, {});
  const LinkBand b = link_band(narrow, wide, 20e6);
  EXPECT_EQ(b.relation, BandRelation::kInBand);
  EXPECT_DOUBLE_EQ(b.offset_hz, 3e6);
  // The other way round the wide signal's flat mask puts 1/20 of its power in
  // the narrow receiver's band.
  const LinkBand back = link_band(wide, narrow, 20e6);
  EXPECT_EQ(back.relation, BandRelation::kLeaking);
  EXPECT_NEAR(back.kappa, 1.0 / 20.0, 1e-6);
}

TEST(RadioTuning, DsssLeaksItsSincSquaredSkirt) {
  const auto* dsss = phy::find_phy("dsss");
  const SpectralMask mask = dsss->spectral_mask(dsss->info.defaults());
  ASSERT_FALSE(mask.points.empty());
  EXPECT_EQ(mask.points.front().dbr, 0.0);
  // The skirt falls: a channel one chip rate away gets less than the adjacent half.
  const double half = mask_power_fraction(mask.points, 0.0, 0.5);
  EXPECT_NEAR(half, 0.5, 1e-9);
  EXPECT_LT(mask_power_fraction(mask.points, 0.3, 0.5), mask_power_fraction(mask.points, 0.1, 0.3));
}

TEST(FrequencyShift, IsAToneAtAbsoluteSampleTimes) {
  const double c = 0.123456;
  std::vector<cf32> x(1000, cf32{1.0F, 0.0F});
  const std::uint64_t first = 5'000'000'123;
  shift_frequency(x, c, first);
  for (std::size_t i = 0; i < x.size(); i += 37) {
    const long double turns = static_cast<long double>(c) * static_cast<long double>(first + i);
    const double phase = 2.0 * std::numbers::pi * static_cast<double>(turns - std::floor(turns));
    EXPECT_NEAR(x[i].real(), std::cos(phase), 2e-6) << i;
    EXPECT_NEAR(x[i].imag(), std::sin(phase), 2e-6) << i;
  }
}

TEST(FrequencyShift, SplitCallsGiveTheWholeCallsSamples) {
  std::vector<cf32> whole(700), a(300), b(400);
  for (std::size_t i = 0; i < whole.size(); ++i) {
    whole[i] = cf32{static_cast<float>(i % 7) - 3.0F, static_cast<float>(i % 5)};
    (i < 300 ? a[i] : b[i - 300]) = whole[i];
  }
  shift_frequency(whole, -0.3, 1000);
  shift_frequency(a, -0.3, 1000);
  shift_frequency(b, -0.3, 1300);
  for (std::size_t i = 0; i < whole.size(); ++i) {
    const cf32 part = i < 300 ? a[i] : b[i - 300];
    EXPECT_NEAR(std::abs(whole[i] - part), 0.0, 1e-5) << i;
  }
}

// ---- the channel with tuned radios ----------------------------------------------

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};
constexpr std::size_t kTick = 200;
constexpr double kFs = 20e6;

/// Two nodes 3 m apart on a 20 Msps grid centred at 2.412 GHz, no noise.
Channel two_nodes() {
  Channel ch(2, make_paper_budget(1.0), kOrigin, ChannelConfig{0.0, false, 7, kFs, kTick, 2.412e9});
  ch.matrix().set_position(0, local_to_ecef({0.0, 0.0, 0.0}, kOrigin));
  ch.matrix().set_position(1, local_to_ecef({3.0, 0.0, 0.0}, kOrigin));
  return ch;
}

/// Unit-power samples of pseudo-random phase.
std::vector<cf32> unit_power(std::size_t n, std::uint32_t seed) {
  std::vector<cf32> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    seed = seed * 1664525U + 1013904223U;
    x[i] = std::polar(1.0F, static_cast<float>(seed >> 8) * 3.7454e-7F);
  }
  return x;
}

TEST(TunedChannel, AnAdjacentChannelArrivesAsNoiseOfTheMasksLeakedPower) {
  Channel ch = two_nodes();
  ch.tune(0, wifi(2.417e9, ofdm_mask()));  // channel 2 transmits
  ch.tune(1, wifi(2.412e9, ofdm_mask()));  // channel 1 listens
  const std::vector<cf32> x = unit_power(kTick, 3);
  const std::vector<Transmission> active{{0, x.data()}};
  Channel::Scratch scratch;
  std::vector<cf32> y(kTick);
  double power = 0.0;
  constexpr int kTicks = 500;
  for (int k = 0; k < kTicks; ++k) {
    ch.on_air(static_cast<SampleTime>(k * kTick), active);
    ASSERT_TRUE(ch.hears_signal(1));
    ch.receive(1, 0, y, scratch);
    for (const cf32 v : y) power += std::norm(v);
  }
  const double g = ch.front_end_gain();
  const double full = std::norm(ch.matrix().coefficient(0, 1)) * g * g;
  // 100000 samples of Gaussian noise: the power is within 1 % of its mean.
  const double leaked_db = 10.0 * std::log10(power / (kTicks * kTick) / full);
  EXPECT_NEAR(leaked_db, standard_mask_fraction_db(5.0, 20.0), 0.1);
  // The link table's gain is the leaked part.
  EXPECT_NEAR(10.0 * std::log10(ch.matrix().power_gain(0, 1) * g * g / full),
              standard_mask_fraction_db(5.0, 20.0), 0.01);
}

TEST(TunedChannel, ANarrowSignalArrivesShiftedByItsOffset) {
  Channel ch = two_nodes();
  RadioTuning narrow = wifi(2.412e9 + 3e6, {});
  narrow.bandwidth_hz = 1e6;
  ch.tune(0, narrow);
  ch.tune(1, wifi(2.412e9 + 1e6, {}));  // the receiver 1 MHz off the grid's centre
  const std::vector<cf32> x = unit_power(kTick, 9);
  const std::vector<Transmission> active{{0, x.data()}};
  Channel::Scratch scratch;
  std::vector<cf32> y(kTick - 50);
  const SampleTime start = 7 * kTick;
  ch.on_air(start, active);
  ch.receive(1, 50, y, scratch);
  const std::complex<double> c =
      std::complex<double>(ch.matrix().coefficient(0, 1)) * ch.front_end_gain();
  for (std::size_t i = 0; i < y.size(); i += 11) {
    const double t = static_cast<double>(start + 50 + static_cast<SampleTime>(i));
    const std::complex<double> want = c * std::complex<double>(x[50 + i]) *
                                      std::polar(1.0, 2.0 * std::numbers::pi * 2e6 / kFs * t);
    EXPECT_NEAR(std::abs(std::complex<double>(y[i]) - want), 0.0, 1e-4 * std::abs(want)) << i;
  }
}

TEST(TunedChannel, AFarChannelIsNotHeardAndCostsNothing) {
  Channel ch = two_nodes();
  ch.tune(0, wifi(2.462e9, ofdm_mask()));  // channel 11
  ch.tune(1, wifi(2.412e9, ofdm_mask()));  // channel 1
  const std::vector<cf32> x = unit_power(kTick, 5);
  const std::vector<Transmission> active{{0, x.data()}};
  ch.on_air(0, active);
  EXPECT_FALSE(ch.hears_signal(1));
  EXPECT_EQ(ch.matrix().power_gain(0, 1), 0.0F);
  EXPECT_NE(ch.matrix().coefficient(0, 1), cf32{});  // the link exists, out of band
  Channel::Scratch scratch;
  std::vector<cf32> y(kTick, cf32{1.0F, 1.0F});
  ch.receive(1, 0, y, scratch);
  for (const cf32 v : y) ASSERT_EQ(v, cf32{});
}

TEST(TunedChannel, UntunedRadiosShareOneBand) {
  Channel ch = two_nodes();
  EXPECT_EQ(ch.band(0, 1).relation, BandRelation::kInBand);
  EXPECT_EQ(ch.matrix().band_gain(0, 1), 1.0F);
  EXPECT_EQ(ch.matrix().power_gain(0, 1), std::norm(ch.matrix().coefficient(0, 1)));
}

}  // namespace
}  // namespace rfsitl::channel
