// The path_loss stage: each model against its textbook formula, written out
// here independently of the implementation.
#include "rfsitl/channel/stages/path_loss.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::channel {
namespace {

constexpr float kInvSqrt2 = 0.70710678118654752f;  // (1+j)/sqrt2: each component
constexpr double kC = 299792458.0;

/// Two nodes `d` metres apart horizontally, at heights ht and hr.
LinkGeometry link(double d, double ht = 10.0, double hr = 10.0) {
  LinkGeometry g;
  g.tx.index = 0;
  g.rx.index = 1;
  g.tx.local = {0.0, 0.0, ht};
  g.rx.local = {d, 0.0, hr};
  g.horizontal_m = d;
  g.distance_m = std::hypot(d, ht - hr);
  return g;
}

std::unique_ptr<GainStage> stage(const std::string& model, double carrier_hz = 2.4e9,
                                 void (*tweak)(config::Settings&) = nullptr) {
  const ChannelStageComponent* c = find_channel_stage("path_loss");
  EXPECT_NE(c, nullptr);
  config::Settings s = c->info.defaults();
  s.set("model", model);
  if (tweak != nullptr) tweak(s);
  c->info.validate(s);
  return c->make(s, StageContext{carrier_hz, 1, 0, "", {}});
}

double gain_db(const GainStage& st, const LinkGeometry& g) {
  return 10.0 * std::log10(std::norm(st.gain(g)));
}

// ---- paper ---------------------------------------------------------------------------

void expect_paper_coefficient(const LinkBudget& b, double d, float path_loss) {
  LinkGeometry g = link(d, 0.0, 0.0);
  const cf32 c = b.coefficient(g);
  EXPECT_FLOAT_EQ(c.real(), kInvSqrt2 * path_loss) << "d = " << d;
  EXPECT_FLOAT_EQ(c.imag(), kInvSqrt2 * path_loss) << "d = " << d;
}

TEST(PaperPathLoss, ExponentThreeGivesOneEighthAndOneThousandth) {
  const auto b = make_paper_budget(3.0);
  expect_paper_coefficient(*b, 1.0, 1.0F / 8.0F);
  expect_paper_coefficient(*b, 9.0, 1.0F / 1000.0F);
}

TEST(PaperPathLoss, ExponentTwoGivesInverseSquare) {
  const auto b = make_paper_budget(2.0);
  expect_paper_coefficient(*b, 1.0, 0.25F);
  expect_paper_coefficient(*b, 99.0, 1e-4F);
}

TEST(PaperPathLoss, ExponentZeroIsDistanceIndependent) {
  const auto b = make_paper_budget(0.0);
  expect_paper_coefficient(*b, 0.0, 1.0F);
  expect_paper_coefficient(*b, 12345.0, 1.0F);
}

TEST(PaperPathLoss, SelfLinkHasUnitPowerGain) {
  LinkGeometry self;  // distance 0, the diagonal
  EXPECT_FLOAT_EQ(std::norm(make_paper_budget(3.0)->coefficient(self)), 1.0F);
}

TEST(PaperPathLoss, PowerGainIsDistancePlusOneToMinusTwiceExponent) {
  const auto b = make_paper_budget(3.0);
  for (const double d : {0.5, 3.0, 40.0, 700.0}) {
    EXPECT_NEAR(std::norm(b->coefficient(link(d, 0.0, 0.0))) / std::pow(d + 1.0, -6.0), 1.0, 1e-6);
  }
}

TEST(PaperPathLoss, TheStageMatchesTheBudgetBitForBit) {
  // The scenario's stage form and the short form are one model.
  const auto st = stage("paper");
  const auto b = make_paper_budget(3.0);
  for (const double d : {0.0, 1.0, 17.3, 250.0}) {
    const std::complex<double> g = st->gain(link(d, 0.0, 0.0));
    const cf32 c = b->coefficient(link(d, 0.0, 0.0));
    EXPECT_EQ(static_cast<float>(g.real()), c.real());
    EXPECT_EQ(static_cast<float>(g.imag()), c.imag());
  }
}

TEST(PaperPathLoss, RejectsNegativeOrNonFiniteExponent) {
  EXPECT_THROW(make_paper_budget(-1.0), std::invalid_argument);
  EXPECT_THROW(make_paper_budget(std::nan("")), std::invalid_argument);
  EXPECT_THROW(make_paper_budget(INFINITY), std::invalid_argument);
}

// ---- free space and log-distance -------------------------------------------------------

TEST(FreeSpacePathLoss, EqualsFriis) {
  const auto st = stage("free_space", 2.4e9);
  for (const double d : {1.0, 10.0, 1000.0, 25000.0}) {
    const double lambda = kC / 2.4e9;
    const double friis_db = 10.0 * std::log10(std::pow(lambda / (4.0 * std::numbers::pi * d), 2));
    EXPECT_NEAR(gain_db(*st, link(d)), friis_db, 1e-9) << d;
  }
  // The textbook figure: 100 m at 2.4 GHz loses 80.05 dB.
  EXPECT_NEAR(path_loss::free_space_db(100.0, 2.4e9), 80.05, 0.01);
}

TEST(FreeSpacePathLoss, SixDecibelsPerDoublingOfDistanceOrFrequency) {
  EXPECT_NEAR(path_loss::free_space_db(200.0, 1e9) - path_loss::free_space_db(100.0, 1e9),
              20.0 * std::log10(2.0), 1e-9);
  EXPECT_NEAR(path_loss::free_space_db(100.0, 2e9) - path_loss::free_space_db(100.0, 1e9),
              20.0 * std::log10(2.0), 1e-9);
}

TEST(FreeSpacePathLoss, ShorterThanTheMinimumCountsAsTheMinimum) {
  const auto st = stage("free_space", 2.4e9);
  EXPECT_DOUBLE_EQ(gain_db(*st, link(0.2)), gain_db(*st, link(1.0)));
  LinkGeometry self;
  EXPECT_TRUE(std::isfinite(gain_db(*st, self)));
}

TEST(LogDistancePathLoss, FreeSpaceToTheReferenceThenItsExponent) {
  const auto st = stage("log_distance", 5.8e9, [](config::Settings& s) {
    s.set("exponent", 3.5);
    s.set("reference_distance_m", 10.0);
  });
  EXPECT_NEAR(gain_db(*st, link(10.0)), -path_loss::free_space_db(10.0, 5.8e9), 1e-9);
  // A decade beyond d0 costs 10 n dB more.
  EXPECT_NEAR(gain_db(*st, link(10.0)) - gain_db(*st, link(100.0)), 35.0, 1e-9);
  EXPECT_NEAR(gain_db(*st, link(10.0)) - gain_db(*st, link(1000.0)), 70.0, 1e-9);
}

// ---- two-ray ----------------------------------------------------------------------------

TEST(TwoRayPathLoss, EqualsTheSumOfTheDirectAndTheReflectedRay) {
  const double f = 2.4e9, lambda = kC / f, k = 2.0 * std::numbers::pi / lambda;
  const double ht = 30.0, hr = 2.0;
  const auto st = stage("two_ray", f);
  for (const double d : {5.0, 57.0, 300.0, 2000.0, 10000.0}) {
    const double r1 = std::sqrt(d * d + (ht - hr) * (ht - hr));
    const double r2 = std::sqrt(d * d + (ht + hr) * (ht + hr));
    const std::complex<double> e = std::polar(1.0 / r1, -k * r1) - std::polar(1.0 / r2, -k * r2);
    const double want_db = 10.0 * std::log10(std::norm(lambda / (4.0 * std::numbers::pi) * e));
    // Long links: the direct formula loses digits to cancellation, the
    // implementation does not, so the tolerance grows with d.
    EXPECT_NEAR(gain_db(*st, link(d, ht, hr)), want_db, d < 1000.0 ? 1e-6 : 0.05) << d;
  }
}

TEST(TwoRayPathLoss, FallsAsDistanceToTheFourthBeyondTheBreakpoint) {
  const double f = 2.4e9, ht = 20.0, hr = 1.5;
  const double dc = path_loss::two_ray_crossover_m(ht, hr, f);
  EXPECT_NEAR(dc, 4.0 * ht * hr / (kC / f), 1e-9);
  const auto st = stage("two_ray", f);
  // Far beyond d_c: |g|^2 = (ht hr)^2 / d^4 (Rappaport eq. 4.52).
  for (const double d : {20 * dc, 100 * dc}) {
    EXPECT_NEAR(gain_db(*st, link(d, ht, hr)),
                10.0 * std::log10(std::pow(ht * hr, 2) / std::pow(d, 4)), 0.1)
        << d;
  }
  // Around d_c is the last peak: 6 dB above free space (the rays add in phase),
  // and beyond it the gain only falls.
  const double peak = gain_db(*st, link(dc, ht, hr));
  EXPECT_NEAR(peak + path_loss::free_space_db(std::hypot(dc, ht - hr), f), 20 * std::log10(2.0),
              0.1);
  double previous = peak;
  for (double d = dc * 1.05; d < dc * 50; d *= 1.05) {
    const double now = gain_db(*st, link(d, ht, hr));
    EXPECT_LT(now, previous) << d;
    previous = now;
  }
}

TEST(TwoRayPathLoss, GroundLevelAntennasCancel) {
  const auto st = stage("two_ray");
  EXPECT_EQ(std::abs(st->gain(link(100.0, 0.0, 0.0))), 0.0);
  // Below the ground counts as on it.
  EXPECT_EQ(std::abs(st->gain(link(100.0, -5.0, 0.0))), 0.0);
}

// ---- the component -----------------------------------------------------------------------

TEST(PathLossStage, DeclaresItsModelsAndLimits) {
  const ChannelStageComponent* c = find_channel_stage("path_loss");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->info.kind, "channel");
  const config::Setting* model = c->info.find("model");
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->choices,
            (std::vector<std::string>{"paper", "free_space", "log_distance", "two_ray",
                                      "tr36777_uma_av", "tr36777_umi_av"}));
  config::Settings bad = c->info.defaults();
  bad.set("reflection", 1.5);
  EXPECT_THROW(c->info.validate(bad), config::SettingError);
}

}  // namespace
}  // namespace rfsitl::channel
