// Student's t and the 95 % intervals over seeds, against the closed forms of
// the t distribution for 1, 2 and 3 degrees of freedom.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/metric_plot.hpp"
#include "rfsitl/campaign/statistics.hpp"

namespace rfsitl::campaign {
namespace {

constexpr double kPi = std::numbers::pi;

// Closed-form CDFs: 1 dof (Cauchy), 2 and 3 dof.
double cdf1(double t) {
  return 0.5 + std::atan(t) / kPi;
}
double cdf2(double t) {
  return 0.5 + t / (2.0 * std::sqrt(2.0 + t * t));
}
double cdf3(double t) {
  const double u = t / std::sqrt(3.0);
  return 0.5 + (u / (1.0 + u * u) + std::atan(u)) / kPi;
}

TEST(CampaignStatistics, TCdfMatchesClosedForms) {
  for (const double t : {-7.0, -1.3, 0.0, 0.4, 2.0, 12.7}) {
    EXPECT_NEAR(student_t_cdf(t, 1), cdf1(t), 1e-12) << t;
    EXPECT_NEAR(student_t_cdf(t, 2), cdf2(t), 1e-12) << t;
    EXPECT_NEAR(student_t_cdf(t, 3), cdf3(t), 1e-12) << t;
  }
}

TEST(CampaignStatistics, TQuantileInvertsTheClosedForms) {
  // 1 dof: t = tan(pi (p - 1/2)); 2 dof: t = (2p - 1) / sqrt(2 p (1 - p)).
  for (const double p : {0.6, 0.9, 0.975, 0.995}) {
    EXPECT_NEAR(student_t_quantile(p, 1), std::tan(kPi * (p - 0.5)), 1e-9) << p;
    EXPECT_NEAR(student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-9) << p;
    EXPECT_NEAR(cdf3(student_t_quantile(p, 3)), p, 1e-12) << p;
  }
  EXPECT_NEAR(student_t_quantile(0.025, 4), -student_t_quantile(0.975, 4), 1e-9);
}

TEST(CampaignStatistics, IntervalIsTTimesTheStandardError) {
  const MeanInterval r = mean_ci95({1.0, 2.0, 3.0, 4.0});
  EXPECT_EQ(r.n, 4U);
  EXPECT_DOUBLE_EQ(r.mean, 2.5);
  // s^2 = (2.25 + 0.25 + 0.25 + 2.25) / 3; the half-width h has F3(h sqrt(n) / s) = 0.975.
  const double s = std::sqrt(5.0 / 3.0);
  EXPECT_NEAR(cdf3(r.half_width * 2.0 / s), 0.975, 1e-12);
  const MeanInterval one = mean_ci95({7.0});
  EXPECT_EQ(one.mean, 7.0);
  EXPECT_EQ(one.half_width, 0.0);
  // Two values: 1 dof, h = tan(0.475 pi) * |a - b| / 2 (s = |a - b| / sqrt 2, n = 2).
  EXPECT_NEAR(mean_ci95({3.0, 5.0}).half_width, std::tan(0.475 * kPi) * 1.0, 1e-9);
}

ResultRow ok_row(std::string x, std::string hue, double metric) {
  ResultRow r;
  r.values = {std::move(x), std::move(hue)};
  r.status = std::string(kStatusOk);
  r.figures["m"] = std::to_string(metric);
  return r;
}

TEST(CampaignPlot, OneSeriesPerOtherParameterMeansOverSeeds) {
  ResultsTable t{{"x", "mac"}, {}};
  for (const double v : {1.0, 3.0}) t.rows.push_back(ok_row("10", "none", v));
  for (const double v : {5.0, 7.0}) t.rows.push_back(ok_row("2", "none", v));
  for (const double v : {4.0, 4.0}) t.rows.push_back(ok_row("10", "csma", v));
  ResultRow failed = ok_row("2", "csma", 100.0);
  failed.status = std::string(kStatusFailed);  // left out
  t.rows.push_back(failed);
  const MetricPlot p = metric_plot(t, "m", "x");
  ASSERT_EQ(p.series.size(), 2U);
  EXPECT_EQ(p.series[0].label, "mac=none");
  ASSERT_EQ(p.series[0].points.size(), 2U);
  EXPECT_EQ(p.series[0].points[0].x, 2.0);  // sorted by the number, not the text
  EXPECT_DOUBLE_EQ(p.series[0].points[0].y.mean, 6.0);
  EXPECT_DOUBLE_EQ(p.series[0].points[1].y.mean, 2.0);
  ASSERT_EQ(p.series[1].points.size(), 1U);
  EXPECT_DOUBLE_EQ(p.series[1].points[0].y.mean, 4.0);
  EXPECT_EQ(p.series[1].points[0].y.half_width, 0.0);
  const std::string svg = svg_of(p);
  EXPECT_NE(svg.find("data-series=\"mac=none\" data-x=\"2\" data-mean=\"6\""), std::string::npos);
  EXPECT_THROW(metric_plot(t, "m", "nope"), CampaignError);
  EXPECT_THROW(metric_plot(t, "nope", "x"), CampaignError);
}

}  // namespace
}  // namespace rfsitl::campaign
