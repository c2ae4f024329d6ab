#include "rfsitl/channel/noise_source.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace rfsitl::channel {
namespace {

struct Moments {
  double mean_i = 0, mean_q = 0;
  double var_i = 0, var_q = 0;  // about the sample mean
  double power = 0;             // E|eta|^2, about zero (the setting's definition)
  double cov_iq = 0;
  double kurtosis_i = 0;  // E[(I - mean)^4] / var^2; 3 for a Gaussian
};

Moments measure(const std::vector<cf32>& v) {
  Moments m;
  const auto n = static_cast<double>(v.size());
  for (const cf32& s : v) {
    m.mean_i += s.real();
    m.mean_q += s.imag();
  }
  m.mean_i /= n;
  m.mean_q /= n;
  double m4 = 0;
  for (const cf32& s : v) {
    const double di = s.real() - m.mean_i;
    const double dq = s.imag() - m.mean_q;
    m.var_i += di * di;
    m.var_q += dq * dq;
    m.cov_iq += di * dq;
    m4 += di * di * di * di;
    m.power += static_cast<double>(std::norm(s));
  }
  m.var_i /= n;
  m.var_q /= n;
  m.cov_iq /= n;
  m.power /= n;
  m.kurtosis_i = (m4 / n) / (m.var_i * m.var_i);
  return m;
}

void check_statistics(std::uint64_t seed, float variance) {
  constexpr std::size_t kN = 1'000'000;
  NoiseSource src(seed, 3, variance);
  EXPECT_EQ(src.variance(), variance);
  std::vector<cf32> v(kN);
  src.fill(v, 0);
  const Moments m = measure(v);
  const double var = variance;
  std::printf(
      "[ noise    ] variance %.3g: measured E|eta|^2 %.6g (%.4f of setting), "
      "var I %.4f, var Q %.4f of setting, mean I %.3g, mean Q %.3g sigma, kurtosis %.4f\n",
      var, m.power, m.power / var, m.var_i / var, m.var_q / var, m.mean_i / std::sqrt(var / 2),
      m.mean_q / std::sqrt(var / 2), m.kurtosis_i);

  EXPECT_NEAR(m.power / var, 1.0, 0.02);
  EXPECT_NEAR(m.var_i / var, 0.5, 0.01);  // 2% of variance/2
  EXPECT_NEAR(m.var_q / var, 0.5, 0.01);
  // Standard error of the mean is sigma/sqrt(N) = 0.001 sigma; allow 5 of them.
  const double sigma_dim = std::sqrt(var / 2);
  EXPECT_LT(std::abs(m.mean_i), 0.005 * sigma_dim);
  EXPECT_LT(std::abs(m.mean_q), 0.005 * sigma_dim);
  // I and Q uncorrelated (circular noise): normalized covariance ~ 0.
  EXPECT_LT(std::abs(m.cov_iq) / (var / 2), 0.01);
  // Gaussian rather than e.g. uniform (1.8) or Laplacian (6).
  EXPECT_NEAR(m.kurtosis_i, 3.0, 0.05);
}

TEST(NoiseSource, EveryKernelGivesTheSameBits) {
  // A seed must name the same noise on any CPU: the AVX2 and AVX-512 kernels
  // against the scalar one, from starts inside and on the edges of the
  // 32-sample groups and across 2^32 Philox blocks.
  const NoiseSource src(12345, 7, 2.0F);
  int compared = 0;
  for (const std::uint64_t first : {0ULL, 5ULL, 31ULL, 32ULL, 123456789ULL, (1ULL << 37) - 3}) {
    for (const std::size_t n : {1U, 7U, 250U, 1000U}) {
      std::vector<cf32> want(n);
      src.add_to(want, first, NoiseKernel::kScalar);
      for (const NoiseKernel k : {NoiseKernel::kAvx2, NoiseKernel::kAvx512, NoiseKernel::kBest}) {
        if (!noise_kernel_supported(k)) continue;
        std::vector<cf32> got(n);
        src.add_to(got, first, k);
        EXPECT_EQ(std::memcmp(got.data(), want.data(), n * sizeof(cf32)), 0)
            << "kernel " << static_cast<int>(k) << " first " << first << " n " << n;
        ++compared;
      }
    }
  }
  std::printf("[ noise    ] %d buffers compared bit for bit with the scalar kernel\n", compared);
  EXPECT_GT(compared, 0);
}

TEST(NoiseSource, SamplesAreBoxMullerOfTheirPhiloxWords) {
  // Sample 32 g + s comes from block 16 g + s mod 16, words 0-1 (s < 16) or
  // 2-3: the kernels' polynomials for ln, cos and sin against double precision.
  const float variance = 2.0F;  // sigma 1 per dimension
  const NoiseSource src(99, 4, variance);
  std::vector<cf32> v(1 << 16);
  src.fill(v, 0);
  double worst = 0.0;
  for (std::size_t t = 0; t < v.size(); ++t) {
    const std::uint64_t block = 16 * (t / 32) + t % 16;
    const PhiloxCounter w = philox4x32(
        {static_cast<std::uint32_t>(block), static_cast<std::uint32_t>(block >> 32), 4, 0},
        philox_key(99));
    const bool second = t % 32 >= 16;
    const std::uint32_t a = second ? w[2] : w[0];
    const std::uint32_t b = second ? w[3] : w[1];
    // u1 as the kernels form it: a rounded to float, plus one.
    const double u1 = (static_cast<double>(static_cast<float>(a)) + 1.0) * 0x1.0p-32;
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double theta = 2.0 * std::numbers::pi * static_cast<double>(b) * 0x1.0p-32;
    worst = std::max(worst, std::abs(v[t].real() - r * std::cos(theta)));
    worst = std::max(worst, std::abs(v[t].imag() - r * std::sin(theta)));
  }
  std::printf("[ noise    ] worst deviation from double-precision Box-Muller: %.3g sigma\n", worst);
  EXPECT_LT(worst, 3e-6);
}

TEST(NoiseSource, MeasuredVarianceWithin2PercentForUnitScale) {
  check_statistics(1, 2.0f);
}

TEST(NoiseSource, MeasuredVarianceWithin2PercentForThermalScale) {
  check_statistics(7, 1e-12f);
}

TEST(NoiseSource, SameSeedAndStreamGiveIdenticalOutput) {
  NoiseSource a(42, 0, 1.0f);
  NoiseSource b(42, 0, 1.0f);
  std::vector<cf32> va(4096), vb(4096);
  a.fill(va, 0);
  b.fill(vb, 0);
  EXPECT_EQ(va, vb);
}

/// No equal samples and a normalised correlation within 5 standard errors of 0.
void expect_independent(const std::vector<cf32>& va, const std::vector<cf32>& vb) {
  std::size_t equal = 0;
  double cross = 0;
  for (std::size_t t = 0; t < va.size(); ++t) {
    equal += (va[t] == vb[t]) ? 1u : 0u;
    cross += static_cast<double>(va[t].real() * vb[t].real());
  }
  EXPECT_EQ(equal, 0u);
  // Independent: normalized correlation ~ N(0, 1/sqrt(4096)) = 0.016.
  EXPECT_LT(std::abs(cross / (0.5 * static_cast<double>(va.size()))), 0.08);
}

TEST(NoiseSource, AdjacentSeedsAndAdjacentStreamsAreIndependent) {
  std::vector<cf32> a(4096), b(4096), c(4096);
  NoiseSource(42, 0, 1.0f).fill(a, 0);
  NoiseSource(43, 0, 1.0f).fill(b, 0);
  NoiseSource(42, 1, 1.0f).fill(c, 0);
  expect_independent(a, b);
  expect_independent(a, c);
  // A stream against itself shifted by one sample: no correlation between
  // neighbouring counters either.
  std::vector<cf32> shifted(4096);
  NoiseSource(42, 0, 1.0f).fill(shifted, 1);
  expect_independent(a, shifted);
}

TEST(NoiseSource, ASampleDependsOnlyOnItsIndexNotOnWhatWasDrawnBefore) {
  const NoiseSource src(5, 2, 1.0f);
  std::vector<cf32> whole(1000), parts(1000);
  src.fill(whole, 7000);
  // Drawn out of order, in uneven pieces, some twice: the same samples.
  src.fill(std::span<cf32>(parts).subspan(300), 7300);
  src.fill(std::span<cf32>(parts).first(1), 7000);
  src.fill(std::span<cf32>(parts).subspan(1, 299), 7001);
  src.fill(std::span<cf32>(parts).subspan(300, 5), 7300);
  EXPECT_EQ(whole, parts);
  // Sample 2^40 + 5 exists like any other (64-bit sample counter).
  std::vector<cf32> far(2);
  src.fill(far, (std::uint64_t{1} << 40) + 5);
  EXPECT_NE(far[0], far[1]);
}

TEST(NoiseSource, AddToAddsTheSameNoiseOnTopOfTheSignal) {
  const NoiseSource src(9, 0, 0.5f);
  std::vector<cf32> noise(256);
  src.fill(noise, 100);
  std::vector<cf32> signal(256, cf32{1.0f, -2.0f});
  src.add_to(signal, 100);
  for (std::size_t t = 0; t < signal.size(); ++t) {
    EXPECT_EQ(signal[t], cf32(1.0f, -2.0f) + noise[t]) << "t " << t;
  }
}

TEST(NoiseSource, ZeroVarianceIsSilentAndAddToLeavesSignalUnchanged) {
  NoiseSource src(3, 0, 0.0f);
  std::vector<cf32> v(64, cf32{5.0f, 5.0f});
  src.add_to(v, 0);
  for (const cf32& s : v) {
    EXPECT_EQ(s, cf32(5.0f, 5.0f));
  }
  src.fill(v, 0);
  for (const cf32& s : v) {
    EXPECT_EQ(s, cf32(0.0f, 0.0f));
  }
}

TEST(NoiseSource, RejectsNegativeOrNonFiniteVariance) {
  EXPECT_THROW(NoiseSource(1, 0, -1.0f), std::invalid_argument);
  EXPECT_THROW(NoiseSource(1, 0, std::nanf("")), std::invalid_argument);
  EXPECT_THROW(NoiseSource(1, 0, INFINITY), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::channel
