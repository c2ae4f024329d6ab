#include "rfsitl/channel/link_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace rfsitl::channel {
namespace {

// (1+j)/sqrt(2): each component is 1/sqrt(2).
constexpr float kInvSqrt2 = 0.70710678118654752f;

void expect_paper_coefficient(const LinkModel& m, double d, float path_loss) {
  const cf32 c = m.coefficient(d);
  EXPECT_FLOAT_EQ(c.real(), kInvSqrt2 * path_loss) << "d = " << d;
  EXPECT_FLOAT_EQ(c.imag(), kInvSqrt2 * path_loss) << "d = " << d;
}

TEST(PaperLinkModel, ExponentThreeGivesOneEighthAndOneThousandth) {
  const auto m = make_paper_link_model(3.0);
  expect_paper_coefficient(*m, 0.0, 1.0f);    // (0 + 1)^-3 = 1
  expect_paper_coefficient(*m, 1.0, 0.125f);  // (1 + 1)^-3 = 1/8
  expect_paper_coefficient(*m, 9.0, 0.001f);  // (9 + 1)^-3 = 1/1000
  expect_paper_coefficient(*m, 99.0, 1e-6f);  // (99 + 1)^-3 = 1e-6
}

TEST(PaperLinkModel, ExponentTwoGivesInverseSquare) {
  const auto m = make_paper_link_model(2.0);
  expect_paper_coefficient(*m, 0.0, 1.0f);
  expect_paper_coefficient(*m, 1.0, 0.25f);    // 2^-2
  expect_paper_coefficient(*m, 3.0, 0.0625f);  // 4^-2
  expect_paper_coefficient(*m, 9.0, 0.01f);    // 10^-2
}

TEST(PaperLinkModel, ExponentZeroIsDistanceIndependent) {
  const auto m = make_paper_link_model(0.0);
  expect_paper_coefficient(*m, 0.0, 1.0f);
  expect_paper_coefficient(*m, 12345.0, 1.0f);
}

TEST(PaperLinkModel, DefaultExponentIsThree) {
  const auto m = make_paper_link_model();
  expect_paper_coefficient(*m, 1.0, 0.125f);
}

TEST(PaperLinkModel, SelfLinkHasUnitPowerGain) {
  // Half duplex: a node hears its own transmission at full strength.
  const cf32 c = make_paper_link_model(3.0)->coefficient(0.0);
  EXPECT_FLOAT_EQ(std::norm(c), 1.0f);
}

TEST(PaperLinkModel, PowerGainIsDistancePlusOneToMinusTwiceExponent) {
  const auto m = make_paper_link_model(3.0);
  EXPECT_NEAR(std::norm(m->coefficient(9.0)), 1e-6, 1e-12);  // 10^-6
}

TEST(PaperLinkModel, GainDecreasesWithDistance) {
  const auto m = make_paper_link_model(3.0);
  EXPECT_GT(std::abs(m->coefficient(10.0)), std::abs(m->coefficient(11.0)));
}

TEST(PaperLinkModel, DescribeNamesFormulaAndExponent) {
  EXPECT_EQ(make_paper_link_model(3.0)->describe(), "paper: c=(1+j)/sqrt2*(d+1)^-3");
  EXPECT_EQ(make_paper_link_model(2.5)->describe(), "paper: c=(1+j)/sqrt2*(d+1)^-2.5");
}

TEST(PaperLinkModel, RejectsNegativeOrNonFiniteExponent) {
  EXPECT_THROW(make_paper_link_model(-1.0), std::invalid_argument);
  EXPECT_THROW(make_paper_link_model(std::nan("")), std::invalid_argument);
  EXPECT_THROW(make_paper_link_model(INFINITY), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::channel
