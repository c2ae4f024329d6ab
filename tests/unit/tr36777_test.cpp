// The TR 36.777 aerial-UE models (UMa-AV, UMi-AV): each formula against points
// computed by hand from the TRs' tables (/tmp/research/tr36777.md section 6,
// fc = 2 GHz, c = 3e8, h_E = 1 m, printed to 5 digits: hence the tolerances),
// and the path_loss stage's LOS draw against its probability.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/channel/stages/tr36777.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::channel {
namespace {

using path_loss::tr36777::los_probability;
using path_loss::tr36777::path_loss_db;
using path_loss::tr36777::Scenario;
using path_loss::tr36777::shadow_fading_sigma_db;

constexpr Scenario kUma = Scenario::kUmaAv;
constexpr Scenario kUmi = Scenario::kUmiAv;
constexpr double kFc = 2e9;
constexpr double kProbabilityTol = 6e-6;  // the points are printed to 5 decimals
constexpr double kDbTol = 6e-4;           // ... and dB values to 3

// ---- the formulas against the hand-computed points (research section 6) -----------------

TEST(Tr36777Formulas, UmaAvLosProbabilityMatchesTableB1Points) {
  // 6.1 UMa-AV, h = 50 m: p1 = 3505.571, d1 = 81.526.
  EXPECT_NEAR(los_probability(kUma, 100.0, 50.0), 0.99480, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 200.0, 50.0), 0.96715, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 500.0, 50.0), 0.88875, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 1000.0, 50.0), 0.77205, kProbabilityTol);
  // 6.1 UMa-AV, h = 30 m (d1 at its 18 m floor) and h = 100 m (d1 = 220 m).
  EXPECT_NEAR(los_probability(kUma, 500.0, 30.0), 0.82846, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 500.0, 100.0), 0.94460, kProbabilityTol);
}

TEST(Tr36777Formulas, UmiAvLosProbabilityMatchesTableB1Points) {
  // 6.1 UMi-AV, h = 50 m (p1 = 396.575, d1 = 66.642), 30 m and 300 m.
  EXPECT_NEAR(los_probability(kUmi, 100.0, 50.0), 0.92565, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 500.0, 50.0), 0.37894, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 500.0, 30.0), 0.26197, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 500.0, 300.0), 0.76332, kProbabilityTol);
}

TEST(Tr36777Formulas, TerrestrialLosProbabilityUpTo22AndAHalfMetres) {
  // 6.1 "Terrestrial": TR 38.901 Table 7.4.2-1, UMa at 1.5 m and 20 m (C' > 0), UMi.
  EXPECT_NEAR(los_probability(kUma, 50.0, 1.5), 0.64940, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 100.0, 1.5), 0.34767, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 500.0, 1.5), 0.03634, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 100.0, 20.0), 0.47835, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUma, 500.0, 20.0), 0.15499, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 50.0, 1.5), 0.51959, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 100.0, 1.5), 0.23098, kProbabilityTol);
  EXPECT_NEAR(los_probability(kUmi, 500.0, 1.5), 0.03600, kProbabilityTol);
  // Section 1: the bands meet discontinuously. 22.5 m itself is terrestrial
  // (0.554 UMa, 0.231 UMi at 100 m); just above, the aerial form (0.960, 0.777).
  EXPECT_NEAR(los_probability(kUma, 100.0, 22.5), 0.554, 6e-4);
  EXPECT_NEAR(los_probability(kUmi, 100.0, 22.5), 0.231, 6e-4);
  EXPECT_NEAR(los_probability(kUma, 100.0, 22.5001), 0.960, 6e-4);
  EXPECT_NEAR(los_probability(kUmi, 100.0, 22.5001), 0.777, 6e-4);
}

TEST(Tr36777Formulas, UmaAvPathLossMatchesTableB2Points) {
  // 6.2 UMa-AV, base station 25 m: (h, d2D) -> LOS, NLOS.
  EXPECT_NEAR(path_loss_db(kUma, true, 500.0, 25.0, 50.0, kFc), 93.410, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 500.0, 25.0, 50.0, kFc), 113.035, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, true, 100.0, 25.0, 50.0, kFc), 78.310, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 100.0, 25.0, 50.0, kFc), 89.626, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, true, 1000.0, 25.0, 100.0, kFc), 100.047, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 1000.0, 25.0, 100.0, kFc), 117.001, kDbTol);
}

TEST(Tr36777Formulas, UmiAvPathLossMatchesTableB2Points) {
  // 6.2 UMi-AV, base station 10 m. At (50 m, 500 m) the fit (94.710) is above
  // free space (92.469), so the max() picks the fit.
  EXPECT_NEAR(path_loss_db(kUmi, true, 500.0, 10.0, 50.0, kFc), 94.710, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, false, 500.0, 10.0, 50.0, kFc), 120.208, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, true, 500.0, 10.0, 100.0, kFc), 94.421, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, false, 500.0, 10.0, 100.0, kFc), 114.186, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, true, 1000.0, 10.0, 300.0, kFc), 100.323, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, false, 1000.0, 10.0, 300.0, kFc), 111.970, kDbTol);
}

TEST(Tr36777Formulas, TerrestrialPathLossMatchesTable741Points) {
  // 6.3 UMa, 25 m / 1.5 m: d'BP = 320 m, so 200 m is PL1 and 500, 1000 m PL2.
  EXPECT_NEAR(path_loss_db(kUma, true, 200.0, 25.0, 1.5, kFc), 84.709, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 200.0, 25.0, 1.5, kFc), 109.601, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, true, 500.0, 25.0, 1.5, kFc), 96.885, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 500.0, 25.0, 1.5, kFc), 125.055, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, true, 1000.0, 25.0, 1.5, kFc), 108.912, kDbTol);
  EXPECT_NEAR(path_loss_db(kUma, false, 1000.0, 25.0, 1.5, kFc), 136.805, kDbTol);
  // 6.3 UMi, 10 m / 1.5 m: d'BP = 120 m, so 100 m is PL1 and 500 m PL2.
  EXPECT_NEAR(path_loss_db(kUmi, true, 100.0, 10.0, 1.5, kFc), 80.453, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, false, 100.0, 10.0, 1.5, kFc), 99.467, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, true, 500.0, 10.0, 1.5, kFc), 106.857, kDbTol);
  EXPECT_NEAR(path_loss_db(kUmi, false, 500.0, 10.0, 1.5, kFc), 124.088, kDbTol);
}

TEST(Tr36777Formulas, ShadowFadingSigmaMatchesTableB3) {
  // 6.2: UMa-AV LOS 4.64 exp(-0.0066 h); UMi-AV LOS max(5 exp(-0.01 h), 2).
  EXPECT_NEAR(shadow_fading_sigma_db(kUma, true, 50.0), 3.3358, 6e-5);
  EXPECT_NEAR(shadow_fading_sigma_db(kUma, true, 100.0), 2.3982, 6e-5);
  EXPECT_NEAR(shadow_fading_sigma_db(kUmi, true, 50.0), 3.0327, 6e-5);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUmi, true, 100.0), 2.0);  // the floor
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUmi, true, 300.0), 2.0);
  // Table B-3 NLOS constants, and TR 38.901's below 22.5 m (section 3.2).
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUma, false, 50.0), 6.0);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUmi, false, 50.0), 8.0);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUma, true, 1.5), 4.0);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUma, false, 22.5), 6.0);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUmi, true, 1.5), 4.0);
  EXPECT_DOUBLE_EQ(shadow_fading_sigma_db(kUmi, false, 22.5), 7.82);
}

TEST(Tr36777Formulas, LosIsCertainBelowD1AndForUmaAbove100Metres) {
  // UMa-AV, h = 50 m: d1 = 460 log10(50) - 700 = 81.526 m.
  EXPECT_EQ(los_probability(kUma, 0.0, 50.0), 1.0);
  EXPECT_EQ(los_probability(kUma, 81.5, 50.0), 1.0);
  EXPECT_LT(los_probability(kUma, 81.6, 50.0), 1.0);
  EXPECT_EQ(los_probability(kUma, 200.0, 100.0), 1.0);  // d1 = 220 m at 100 m
  for (const double h : {100.01, 150.0, 300.0}) {
    for (const double d : {10.0, 1000.0, 4000.0}) EXPECT_EQ(los_probability(kUma, d, h), 1.0);
  }
  // UMi-AV keeps the d <= d1 branch (h = 300 m: d1 = 294.05 log10(300) - 432.94
  // = 295.458 m) and so never exceeds 1; the terrestrial forms are 1 to 18 m.
  EXPECT_EQ(los_probability(kUmi, 295.4, 300.0), 1.0);
  EXPECT_EQ(los_probability(kUmi, 50.0, 50.0), 1.0);
  for (double d = 0.0; d < 1000.0; d += 7.0) EXPECT_LE(los_probability(kUmi, d, 100.0), 1.0);
  EXPECT_EQ(los_probability(kUma, 18.0, 20.0), 1.0);
  EXPECT_EQ(los_probability(kUmi, 18.0, 1.5), 1.0);
}

// ---- the stage ----------------------------------------------------------------------------

/// Nodes i and j, `d2d` metres apart horizontally, at heights zi and zj.
LinkGeometry link_between(std::size_t i, std::size_t j, double d2d, double zi, double zj) {
  LinkGeometry g;
  g.tx.index = i;
  g.rx.index = j;
  g.tx.local = {0.0, 0.0, zi};
  g.rx.local = {d2d, 0.0, zj};
  g.horizontal_m = d2d;
  g.distance_m = std::hypot(d2d, zi - zj);
  return g;
}

std::unique_ptr<GainStage> stage(const std::string& model, const std::string& los,
                                 std::uint64_t seed = 1, std::size_t position = 0) {
  const ChannelStageComponent* c = find_channel_stage("path_loss");
  EXPECT_NE(c, nullptr);
  config::Settings s = c->info.defaults();
  s.set("model", model);
  s.set("los", los);
  c->info.validate(s);
  return c->make(s, StageContext{kFc, seed, position, "", {}});
}

double loss_db(const GainStage& st, const LinkGeometry& g) {
  return -10.0 * std::log10(std::norm(st.gain(g)));
}

/// A geometry for the LOS draw: the base station's and UE's heights, d2D, the
/// probability of LOS and the losses with and without it, all from section 6
/// or, for the terrestrial one, from TR 38.901 written out below.
struct DrawCase {
  std::string model;
  double h_bs, h_ut, d2d, p_los, los_db, nlos_db;
};

DrawCase terrestrial_uma_case() {
  // UMa, base station 2 m, UE 20 m, 100 m: P_LOS = 0.47835 (6.1). d'BP =
  // 4 (2 - 1)(20 - 1) 2e9 / 3e8 = 506.7 m > 100 m, so LOS is PL1; NLOS is
  // max(LOS, 13.54 + 39.08 log10 d3D + 20 log10 fc - 0.6 (hUT - 1.5)).
  const double d3d = std::hypot(100.0, 18.0);
  const double los = 28.0 + 22.0 * std::log10(d3d) + 20.0 * std::log10(2.0);
  const double nlos = 13.54 + 39.08 * std::log10(d3d) + 20.0 * std::log10(2.0) - 0.6 * 18.5;
  return {"tr36777_uma_av", 2.0, 20.0, 100.0, 0.47835, los, std::max(los, nlos)};
}

std::vector<DrawCase> draw_cases() {
  return {{"tr36777_uma_av", 25.0, 50.0, 500.0, 0.88875, 93.410, 113.035},
          {"tr36777_umi_av", 10.0, 50.0, 500.0, 0.37894, 94.710, 120.208},
          terrestrial_uma_case()};
}

constexpr std::size_t kLinks = 20000;

/// Link k joins nodes 2k and 2k + 1, the lower index at either end.
LinkGeometry draw_link(const DrawCase& c, std::size_t k) {
  const bool swap = k % 2 == 1;
  const std::size_t bs = swap ? 2 * k + 1 : 2 * k, ut = swap ? 2 * k : 2 * k + 1;
  return link_between(bs, ut, c.d2d, c.h_bs, c.h_ut);
}

/// Whether the stage gave link k LOS; fails unless it is one of the two losses.
bool stage_says_los(const GainStage& st, const DrawCase& c, std::size_t k) {
  const double db = loss_db(st, draw_link(c, k));
  const bool los = std::abs(db - c.los_db) < kDbTol;
  EXPECT_TRUE(los || std::abs(db - c.nlos_db) < kDbTol) << c.model << " link " << k << ": " << db;
  return los;
}

TEST(Tr36777Stage, DrawnLosFractionMatchesTheProbability) {
  // Binomial: 20000 links, each LOS with p independently. 6 sigma bounds the
  // fraction with a false-failure probability of 2e-9 per geometry (and the
  // seed is fixed, so the outcome never changes).
  for (const DrawCase& c : draw_cases()) {
    const auto st = stage(c.model, "drawn");
    std::size_t los = 0;
    for (std::size_t k = 0; k < kLinks; ++k) los += stage_says_los(*st, c, k) ? 1 : 0;
    const double sigma = std::sqrt(c.p_los * (1.0 - c.p_los) / static_cast<double>(kLinks));
    EXPECT_NEAR(static_cast<double>(los) / kLinks, c.p_los, 6.0 * sigma) << c.model << c.h_ut;
  }
}

TEST(Tr36777Stage, DrawIsPerUnorderedPairAndReciprocal) {
  const DrawCase c = draw_cases()[0];
  const auto st = stage(c.model, "drawn");
  EXPECT_TRUE(st->reciprocal());
  for (std::size_t k = 0; k < 200; ++k) {
    const LinkGeometry g = draw_link(c, k);
    LinkGeometry back = link_between(g.rx.index, g.tx.index, c.d2d, c.h_ut, c.h_bs);
    EXPECT_EQ(st->gain(g), st->gain(back)) << k;
    EXPECT_EQ(st->gain(g), st->gain(g)) << k;  // fixed per link
  }
}

TEST(Tr36777Stage, SeedAndPositionGiveIndependentDraws) {
  // Two independent draws disagree on a link with probability 2 p (1 - p);
  // 6-sigma binomial bound over 20000 links (false failure 2e-9 each).
  const DrawCase c = terrestrial_uma_case();
  const auto base = stage(c.model, "drawn", 1, 0);
  const auto other_seed = stage(c.model, "drawn", 2, 0);
  const auto other_position = stage(c.model, "drawn", 1, 1);
  const double q = 2.0 * c.p_los * (1.0 - c.p_los);
  const double bound = 6.0 * std::sqrt(q * (1.0 - q) / static_cast<double>(kLinks));
  std::size_t seed_differs = 0, position_differs = 0;
  for (std::size_t k = 0; k < kLinks; ++k) {
    const bool los = stage_says_los(*base, c, k);
    seed_differs += los != stage_says_los(*other_seed, c, k) ? 1 : 0;
    position_differs += los != stage_says_los(*other_position, c, k) ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(seed_differs) / kLinks, q, bound);
  EXPECT_NEAR(static_cast<double>(position_differs) / kLinks, q, bound);
}

TEST(Tr36777Stage, ForcedLosAndNlosGiveTheirFormulaOnEveryLink) {
  for (const DrawCase& c : draw_cases()) {
    const auto los = stage(c.model, "los");
    const auto nlos = stage(c.model, "nlos");
    for (std::size_t k = 0; k < 500; ++k) {
      EXPECT_NEAR(loss_db(*los, draw_link(c, k)), c.los_db, kDbTol) << c.model << k;
      EXPECT_NEAR(loss_db(*nlos, draw_link(c, k)), c.nlos_db, kDbTol) << c.model << k;
    }
  }
}

TEST(Tr36777Stage, ThroughTheRegistryGivesTheTableValues) {
  // Default `los` (drawn) where LOS is certain (UMa-AV above 100 m): the UE at
  // 150 m, the base station at 25 m, 1000 m apart, 2 GHz from the context:
  // 28 + 22 log10(d3D) + 20 log10(2).
  const auto drawn = stage("tr36777_uma_av", "drawn");
  const double d3d = std::hypot(1000.0, 125.0);
  const LinkGeometry g = link_between(3, 7, 1000.0, 150.0, 25.0);  // the UE is tx here
  EXPECT_NEAR(loss_db(*drawn, g), 28.0 + 22.0 * std::log10(d3d) + 20.0 * std::log10(2.0), 1e-9);
  // 6.2 UMa-AV (100 m, 1000 m) and UMi-AV (300 m, 1000 m), LOS and NLOS.
  EXPECT_NEAR(loss_db(*stage("tr36777_uma_av", "los"), link_between(0, 1, 1000.0, 25.0, 100.0)),
              100.047, kDbTol);
  EXPECT_NEAR(loss_db(*stage("tr36777_uma_av", "nlos"), link_between(0, 1, 1000.0, 25.0, 100.0)),
              117.001, kDbTol);
  EXPECT_NEAR(loss_db(*stage("tr36777_umi_av", "los"), link_between(0, 1, 1000.0, 10.0, 300.0)),
              100.323, kDbTol);
  EXPECT_NEAR(loss_db(*stage("tr36777_umi_av", "nlos"), link_between(0, 1, 1000.0, 10.0, 300.0)),
              111.970, kDbTol);
}

TEST(Tr36777Stage, HeightsAreClampedToTheModelsRange) {
  // A UE above 300 m counts as at 300 m (6.2 UMi-AV: 100.323 dB at 1000 m).
  const auto los = stage("tr36777_umi_av", "los");
  EXPECT_NEAR(loss_db(*los, link_between(0, 1, 1000.0, 10.0, 450.0)), 100.323, kDbTol);
  // Both ends on (or below) the ground count as 1.5 m: terrestrial UMi with
  // d3D = d2D = 100 m beyond d'BP = 4 * 0.5 * 0.5 * 2e9 / 3e8 = 3.3 m, so PL2
  // with hBS = hUT.
  const double d_bp = 4.0 * 0.5 * 0.5 * 2e9 / 3e8;
  const double pl2 = 32.4 + 40.0 * 2.0 + 20.0 * std::log10(2.0) - 9.5 * std::log10(d_bp * d_bp);
  EXPECT_NEAR(loss_db(*los, link_between(0, 1, 100.0, 0.0, -3.0)), pl2, 1e-9);
  // The diagonal (no distance) stays finite.
  EXPECT_TRUE(std::isfinite(loss_db(*los, link_between(4, 4, 0.0, 30.0, 30.0))));
}

}  // namespace
}  // namespace rfsitl::channel
