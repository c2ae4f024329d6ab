// The shadowing stage: its statistics against the model's laws (a normal
// marginal with the declared sigma, Gudmundson's exp(-r/d) correlation at each
// end), reciprocity, determinism and its declaration.
//
// The statistical tests run on fixed seeds, so they never flake; the stated
// probabilities are those of a correct implementation failing on a fresh seed.
#include "rfsitl/channel/stages/shadowing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "rfsitl/config/settings.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

#include "stage_test_support.hpp"

namespace rfsitl::channel {
namespace {

using rfsitl::testing::link;

using rfsitl::testing::kolmogorov_p_value;
using rfsitl::testing::ks_statistic;
using rfsitl::testing::refused_key;

LinkEnd end(std::size_t index, double x_m, double y_m, double z_m) {
  LinkEnd e;
  e.index = index;
  e.local = {x_m, y_m, z_m};
  return e;
}

LinkEnd moved(LinkEnd e, double dx_m, double dy_m, double dz_m) {
  e.local.x_m += dx_m;
  e.local.y_m += dy_m;
  e.local.z_m += dz_m;
  return e;
}

/// The registered stage with settings `s`, checked as a scenario's are.
std::unique_ptr<GainStage> make_stage(const config::Settings& s, std::uint64_t scenario_seed,
                                      std::size_t position = 0) {
  const ChannelStageComponent* c = find_channel_stage("shadowing");
  EXPECT_NE(c, nullptr);
  c->info.validate(s);
  return c->make(s, StageContext{2.4e9, scenario_seed, position, "", {}});
}

config::Settings settings_with(double sigma_db, std::uint64_t seed = 0) {
  config::Settings s = find_channel_stage("shadowing")->info.defaults();
  s.set("sigma_db", sigma_db);
  s.set("seed", seed);
  return s;
}

double standard_normal_cdf(double x) {
  return 0.5 * std::erfc(-x / std::numbers::sqrt2);
}

/// sup_x |F_n(x) - Phi(x)| for the samples `z` (in units of sigma).
double ks_statistic_against_normal(std::vector<double> z) {
  std::sort(z.begin(), z.end());
  std::vector<double> cdf;
  for (const double x : z) cdf.push_back(standard_normal_cdf(x));
  return ks_statistic(cdf);
}

// ---- (1) the marginal: N(0, sigma^2) over links -------------------------------------------

TEST(ShadowingStatistics, OverManyLinksTheDecibelsAreNormalWithMeanZeroAndStdSigma) {
  const double sigma = 6.0;
  const auto stage = make_stage(settings_with(sigma), 20240611);
  // Every pair of 90 nodes (4005 links), each with its low end at P and its
  // high end at Q: only the draws differ from link to link.
  std::vector<double> z;
  for (std::size_t a = 0; a < 90; ++a) {
    for (std::size_t b = a + 1; b < 90; ++b) {
      const std::complex<double> g =
          stage->gain(link(end(a, 12.0, -40.0, 1.5), end(b, 310.0, 95.0, 30.0)));
      ASSERT_EQ(g.imag(), 0.0);  // phase 0
      ASSERT_GT(g.real(), 0.0);
      z.push_back(20.0 * std::log10(g.real()) / sigma);
    }
  }
  const auto n = static_cast<double>(z.size());
  double sum = 0.0, sum_sq = 0.0;
  for (const double v : z) {
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / n;
  const double variance = (sum_sq - n * mean * mean) / (n - 1.0);
  // The mean of n unit-variance values has std 1/sqrt(n): 5.5 of those is
  // exceeded with probability 4e-8.
  EXPECT_LT(std::abs(mean), 5.5 / std::sqrt(n));
  // The sample variance has relative std sqrt((kurtosis - 1) / n) <= sqrt(2 / n)
  // (a sum of M cosines has kurtosis 3 - 3/(2M) < 3); 6 of those: 2e-9.
  EXPECT_LT(std::abs(variance - 1.0), 6.0 * std::sqrt(2.0 / n))
      << "std/sigma " << std::sqrt(variance);
  // Kolmogorov-Smirnov against the standard normal CDF.
  const double d = ks_statistic_against_normal(z);
  EXPECT_GT(kolmogorov_p_value(d, z.size()), 0.001) << "D = " << d;
}

TEST(ShadowingStatistics, KolmogorovPValueMatchesItsTabulatedCriticalValues) {
  // The textbook large-n critical values: sqrt(n) D = 1.358 at 5%, 1.949 at 0.1%.
  const std::size_t n = 1000000;
  EXPECT_NEAR(kolmogorov_p_value(1.358 / 1000.0, n), 0.05, 0.001);
  EXPECT_NEAR(kolmogorov_p_value(1.949 / 1000.0, n), 0.001, 0.0001);
}

// ---- (2) the correlation: exp(-|delta| / d) at each end -----------------------------------

/// The correlation, over `links` links, between S with the low end at P and
/// the high end at Q and S with them moved by `move_a` and `move_b` (metres).
double correlation_over_links(const ShadowingSettings& s, std::size_t links,
                              const LinkEnd& p_template, const LinkEnd& q_template,
                              const LocalPosition& move_a, const LocalPosition& move_b) {
  double xy = 0.0, xx = 0.0, yy = 0.0;
  for (std::size_t j = 0; j < links; ++j) {
    LinkEnd p = p_template, q = q_template;
    p.index = 2 * j;
    q.index = 2 * j + 1;
    const double x = shadowing::field_db(s, 99, 3, p, q);
    const double y = shadowing::field_db(s, 99, 3, moved(p, move_a.x_m, move_a.y_m, move_a.z_m),
                                         moved(q, move_b.x_m, move_b.y_m, move_b.z_m));
    xy += x * y;
    xx += x * x;
    yy += y * y;
  }
  // The mean is known to be 0, so the correlation is taken about it.
  return xy / std::sqrt(xx * yy);
}

// 20000 links: a correlation estimate from N Gaussian pairs has std (1 - rho^2)
// / sqrt(N) <= 0.0071 (a simulation of the sum of 32 or 4 sinusoids put it
// within 1.15 times that), so 0.05 is more than 6 std: probability < 1e-9.
constexpr std::size_t kLinks = 20000;

TEST(ShadowingCorrelation, MovingOneEndByDeltaLeavesExpMinusDeltaOverD) {
  ShadowingSettings s;  // d = 20 m, M = 32
  s.sigma_db = 8.0;
  const double d = s.decorrelation_m;
  const LinkEnd p = end(0, 5.0, -7.0, 2.0), q = end(1, 140.0, 60.0, 25.0);
  const LocalPosition still{0.0, 0.0, 0.0};
  // Half d along east at the low end; d north-east-ish (0.6, 0.8) at the low end;
  // 2 d up at the high end: the law depends on |delta| only.
  EXPECT_NEAR(correlation_over_links(s, kLinks, p, q, {0.5 * d, 0.0, 0.0}, still), std::exp(-0.5),
              0.05);
  EXPECT_NEAR(correlation_over_links(s, kLinks, p, q, {0.6 * d, 0.8 * d, 0.0}, still),
              std::exp(-1.0), 0.05);
  EXPECT_NEAR(correlation_over_links(s, kLinks, p, q, still, {0.0, 0.0, 2.0 * d}), std::exp(-2.0),
              0.05);
}

TEST(ShadowingCorrelation, MovingBothEndsGivesTheProduct) {
  ShadowingSettings s;
  s.decorrelation_m = 35.0;
  const double d = s.decorrelation_m;
  const LinkEnd p = end(0, -300.0, 20.0, 10.0), q = end(1, 0.0, 0.0, 1.0);
  // exp(-0.5) exp(-1) = exp(-1.5): separable, not exp(-|(0.5, 1)|) = exp(-1.118).
  EXPECT_NEAR(correlation_over_links(s, kLinks, p, q, {0.0, 0.5 * d, 0.0}, {d, 0.0, 0.0}),
              std::exp(-0.5) * std::exp(-1.0), 0.05);
}

TEST(ShadowingCorrelation, TheEnsembleCorrelationIsExactEvenForFewSinusoids) {
  ShadowingSettings s;
  s.sinusoids = 4;
  const double d = s.decorrelation_m;
  const LinkEnd p = end(0, 0.0, 0.0, 0.0), q = end(1, 50.0, 0.0, 0.0);
  EXPECT_NEAR(correlation_over_links(s, kLinks, p, q, {0.0, d, 0.0}, {0.0, 0.0, 0.0}),
              std::exp(-1.0), 0.05);
}

// ---- (3) reciprocity, (4) determinism --------------------------------------------------------

TEST(Shadowing, IsExactlyReciprocal) {
  const auto stage = make_stage(settings_with(10.0), 5);
  EXPECT_TRUE(stage->reciprocal());
  for (std::size_t a = 0; a < 12; ++a) {
    for (std::size_t b = 0; b < 12; ++b) {
      const LinkEnd ea = end(a, 3.0 * static_cast<double>(a), -17.0, 0.5);
      const LinkEnd eb = end(b, 40.0, 11.0 * static_cast<double>(b), 9.0);
      EXPECT_EQ(stage->gain(link(ea, eb)), stage->gain(link(eb, ea))) << a << " " << b;
    }
  }
}

TEST(Shadowing, ANodesLinkToItselfAndZeroSigmaAreUnshadowed) {
  EXPECT_EQ(make_stage(settings_with(10.0), 5)->gain(link(end(3, 1, 2, 3), end(3, 1, 2, 3))),
            std::complex<double>(1.0, 0.0));
  const auto flat = make_stage(settings_with(0.0), 5);
  EXPECT_EQ(flat->gain(link(end(0, 0, 0, 0), end(1, 100, 0, 0))), std::complex<double>(1.0, 0.0));
}

/// Each link of a small scene, in the given order of evaluation.
std::vector<std::complex<double>> gains(const GainStage& stage, bool reverse_order) {
  std::vector<std::complex<double>> out(20);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::size_t i = reverse_order ? out.size() - 1 - k : k;
    out[i] = stage.gain(link(end(i, 10.0 * static_cast<double>(i), 0.0, 1.0),
                             end(i + 20, 0.0, 5.0 * static_cast<double>(i), 2.0)));
  }
  return out;
}

TEST(Shadowing, SameSeedSameValuesInAnyOrderAndOtherSeedOtherValues) {
  const auto first = gains(*make_stage(settings_with(6.0, 1234), 1), false);
  EXPECT_EQ(gains(*make_stage(settings_with(6.0, 1234), 1), true), first);
  // The stage's own seed wins over the scenario's...
  EXPECT_EQ(gains(*make_stage(settings_with(6.0, 1234), 777), false), first);
  // ... and seed 0 means the scenario's.
  EXPECT_EQ(gains(*make_stage(settings_with(6.0, 0), 1234), false), first);
  const auto other_seed = gains(*make_stage(settings_with(6.0, 1235), 1), false);
  const auto other_position = gains(*make_stage(settings_with(6.0, 1234), 1, 1), false);
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_NE(other_seed[i], first[i]) << i;
    EXPECT_NE(other_position[i], first[i]) << i;
  }
}

// ---- (5) the declaration -------------------------------------------------------------------

TEST(Shadowing, IsRegisteredWithItsDeclaredDefaults) {
  const ChannelStageComponent* c = find_channel_stage("shadowing");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->info.name, "shadowing");
  const config::Settings d = c->info.defaults();
  EXPECT_EQ(d.get<double>("sigma_db"), 4.0);
  EXPECT_EQ(d.get<double>("decorrelation_m"), 20.0);
  EXPECT_EQ(d.get<std::uint64_t>("sinusoids"), 32u);
  EXPECT_EQ(d.get<std::uint64_t>("seed"), 0u);
  EXPECT_NO_THROW(c->info.validate(d));
}

TEST(Shadowing, RefusesSettingsOutOfRangeNamingTheKey) {
  EXPECT_EQ(refused_key("shadowing", "sigma_db", 30.5), "sigma_db");
  EXPECT_EQ(refused_key("shadowing", "sigma_db", -1.0), "sigma_db");
  EXPECT_EQ(refused_key("shadowing", "decorrelation_m", 0.05), "decorrelation_m");
  EXPECT_EQ(refused_key("shadowing", "decorrelation_m", 2e5), "decorrelation_m");
  EXPECT_EQ(refused_key("shadowing", "sinusoids", std::uint64_t{3}), "sinusoids");
  EXPECT_EQ(refused_key("shadowing", "sinusoids", std::uint64_t{1025}), "sinusoids");
  EXPECT_EQ(refused_key("shadowing", "sinusoids", std::uint64_t{1024}), "(accepted)");
}

}  // namespace
}  // namespace rfsitl::channel
