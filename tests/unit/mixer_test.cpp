#include "rfsitl/channel/mixer.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::channel {
namespace {

TEST(Mixer, ThreeNodeSuperpositionMatchesHandComputation) {
  // Three nodes 0, 1, 3 m east of an origin: d01 = 1, d12 = 2, d02 = 3.
  // With exponent 3, PL = (d+1)^-3:
  //   PL00 = PL11 = PL22 = 1, PL01 = 1/8, PL12 = 1/27, PL02 = 1/64.
  const GeodeticPosition origin{43.0, -78.8, 200.0};
  ChannelMatrix m(3, make_paper_budget(3.0));
  m.set_position(0, local_to_ecef({0.0, 0.0, 0.0}, origin));
  m.set_position(1, local_to_ecef({1.0, 0.0, 0.0}, origin));
  m.set_position(2, local_to_ecef({3.0, 0.0, 0.0}, origin));

  const std::array<cf32, 2> x0{cf32{1, 0}, cf32{0, 1}};
  const std::array<cf32, 2> x1{cf32{8, 0}, cf32{8, -8}};
  const std::array<cf32, 2> x2{cf32{0, 64}, cf32{64, 0}};
  const std::array<const cf32*, 3> inputs{x0.data(), x1.data(), x2.data()};

  // y_m[t] = (1+j)/sqrt2 * s_m[t] with s_m[t] = sum_n PL_nm x_n[t], and
  // (1+j)/sqrt2 * (a + jb) = ((a - b) + j(a + b)) / sqrt2.
  //
  // s_0[0] = 1*1 + 1/8*8 + 1/64*64j             = 2 + 1j
  //   y_0[0] = (1 + 3j)/sqrt2                     = 0.707107 + 2.121320j
  // s_0[1] = 1*j + 1/8*(8-8j) + 1/64*64         = 2 + 0j
  //   y_0[1] = (2 + 2j)/sqrt2                     = 1.414214 + 1.414214j
  // s_1[0] = 1/8*1 + 1*8 + 1/27*64j             = 8.125 + 2.370370j
  //   y_1[0] = (5.754630 + 10.495370j)/sqrt2      = 4.069138 + 7.421348j
  // s_1[1] = 1/8*j + (8-8j) + 1/27*64           = 10.370370 - 7.875j
  //   y_1[1] = (18.245370 + 2.495370j)/sqrt2      = 12.901425 + 1.764493j
  // s_2[0] = 1/64*1 + 1/27*8 + 64j              = 0.311921 + 64j
  //   y_2[0] = (-63.688079 + 64.311921j)/sqrt2    = -45.034272 + 45.475396j
  // s_2[1] = 1/64*j + 1/27*(8-8j) + 64          = 64.296296 - 0.280671j
  //   y_2[1] = (64.576968 + 64.015625j)/sqrt2     = 45.662812 + 45.265883j
  const std::array<std::array<cf32, 2>, 3> expected{{
      {cf32{0.707107f, 2.121320f}, cf32{1.414214f, 1.414214f}},
      {cf32{4.069138f, 7.421348f}, cf32{12.901425f, 1.764493f}},
      {cf32{-45.034272f, 45.475396f}, cf32{45.662812f, 45.265883f}},
  }};

  for (std::size_t rx = 0; rx < 3; ++rx) {
    std::array<cf32, 2> y{};
    mix(inputs, m.receiver_row(rx), y);
    for (std::size_t t = 0; t < 2; ++t) {
      EXPECT_NEAR(y[t].real(), expected[rx][t].real(), 1e-4) << "rx " << rx << " t " << t;
      EXPECT_NEAR(y[t].imag(), expected[rx][t].imag(), 1e-4) << "rx " << rx << " t " << t;
    }
  }
}

TEST(Mixer, NoInputsZeroFillsOutput) {
  std::vector<cf32> out(5, cf32{7.0f, -3.0f});
  mix({}, {}, out);
  for (const cf32& v : out) {
    EXPECT_EQ(v, cf32(0.0f, 0.0f));
  }
}

TEST(Mixer, AllZeroCoefficientsZeroFillOutput) {
  const std::vector<cf32> x(4, cf32{1.0f, 1.0f});
  const std::array<const cf32*, 1> inputs{x.data()};
  const std::array<cf32, 1> coeffs{cf32{0.0f, 0.0f}};
  std::vector<cf32> out(4, cf32{7.0f, -3.0f});
  mix(inputs, coeffs, out);
  for (const cf32& v : out) {
    EXPECT_EQ(v, cf32(0.0f, 0.0f));
  }
}

TEST(Mixer, SingleInputIsComplexScaled) {
  // (2 + 3j)(1 - 1j) = 2 - 2j + 3j + 3 = 5 + 1j;  (2 + 3j)(0.5j) = -1.5 + 1j.
  const std::array<cf32, 2> x{cf32{1.0f, -1.0f}, cf32{0.0f, 0.5f}};
  const std::array<const cf32*, 1> inputs{x.data()};
  const std::array<cf32, 1> coeffs{cf32{2.0f, 3.0f}};
  std::array<cf32, 2> out{};
  mix(inputs, coeffs, out);
  EXPECT_EQ(out[0], cf32(5.0f, 1.0f));
  EXPECT_EQ(out[1], cf32(-1.5f, 1.0f));
}

TEST(Mixer, MatchesStdComplexReferenceAcrossBlockAndTailLengths) {
  // Lengths around the kernel's 16-sample block exercise both the blocked loop
  // and the scalar tail; a zero coefficient in the middle is skipped.
  const std::array<cf32, 4> coeffs{cf32{0.3f, -0.7f}, cf32{-1.1f, 0.2f}, cf32{0.0f, 0.0f},
                                   cf32{0.05f, 0.9f}};
  for (std::size_t len : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 37u, 1024u}) {
    std::vector<std::vector<cf32>> x(coeffs.size(), std::vector<cf32>(len));
    for (std::size_t i = 0; i < x.size(); ++i) {
      for (std::size_t t = 0; t < len; ++t) {
        // Deterministic, non-repeating pattern with both signs.
        x[i][t] = cf32{std::sin(static_cast<float>(3 * t + i)),
                       std::cos(static_cast<float>(t * t + 7 * i))};
      }
    }
    std::vector<const cf32*> inputs;
    for (const auto& v : x) {
      inputs.push_back(v.data());
    }
    std::vector<cf32> out(len, cf32{99.0f, 99.0f});
    mix(inputs, coeffs, out);
    for (std::size_t t = 0; t < len; ++t) {
      std::complex<double> want{0.0, 0.0};
      for (std::size_t i = 0; i < x.size(); ++i) {
        want += std::complex<double>(coeffs[i]) * std::complex<double>(x[i][t]);
      }
      EXPECT_NEAR(out[t].real(), want.real(), 1e-5) << "len " << len << " t " << t;
      EXPECT_NEAR(out[t].imag(), want.imag(), 1e-5) << "len " << len << " t " << t;
    }
  }
}

TEST(Mixer, MoreInputsThanOneKernelGroupAreAllSummed) {
  // 600 inputs: more than the 256 the kernel takes per call, so the sum is
  // built group by group; input i is the constant (i + 1) with coefficient j.
  constexpr std::size_t kInputs = 600;
  constexpr std::size_t kLen = 40;
  std::vector<std::vector<cf32>> x(kInputs);
  std::vector<const cf32*> inputs;
  std::vector<cf32> coeffs(kInputs, cf32{0.0f, 1.0f});
  for (std::size_t i = 0; i < kInputs; ++i) {
    x[i].assign(kLen, cf32{static_cast<float>(i + 1), 0.0f});
    inputs.push_back(x[i].data());
  }
  std::vector<cf32> out(kLen);
  mix(inputs, coeffs, out);
  const float sum = kInputs * (kInputs + 1) / 2.0f;  // 180300, exact in float
  for (const cf32& v : out) {
    EXPECT_EQ(v.real(), 0.0f);
    EXPECT_EQ(v.imag(), sum);
  }
}

TEST(Mixer, MixRowsEqualsMixRowByRowBitForBit) {
  // Several receivers at once must give each exactly what mix() gives it
  // alone: the engine groups receivers by what else runs in the tick, and that
  // must not change any receiver's input. Row counts 1..9 cover full groups of
  // four and remainders; lengths cover whole blocks, short rests and masked
  // tails; zeros on the diagonal (a receiver's own input), a column zero in
  // every row, and scattered zeros cover the inputs left out.
  std::uint32_t state = 12345;
  const auto next = [&] {
    state = state * 1664525U + 1013904223U;
    return static_cast<float>(state >> 8) / static_cast<float>(1U << 24) - 0.5F;
  };
  for (const std::size_t n_in : {1u, 3u, 13u, 16u, 40u}) {
    for (const std::size_t rows : {1u, 2u, 3u, 4u, 5u, 9u}) {
      for (const std::size_t len : {1u, 7u, 8u, 10u, 23u, 24u, 31u, 250u, 1000u}) {
        std::vector<std::vector<cf32>> x(n_in, std::vector<cf32>(len));
        std::vector<const cf32*> inputs;
        for (auto& v : x) {
          for (auto& s : v) s = {next(), next()};
          inputs.push_back(v.data());
        }
        std::vector<cf32> coeffs(rows * n_in);
        for (std::size_t r = 0; r < rows; ++r) {
          for (std::size_t i = 0; i < n_in; ++i) {
            const bool zero = r == i || (n_in > 2 && i == 2) || (r + 3 * i) % 7 == 0;
            coeffs[r * n_in + i] = zero ? cf32{} : cf32{next(), next()};
          }
        }
        // Eight guard samples after each output: the masked tail writes none.
        std::vector<std::vector<cf32>> outs(rows, std::vector<cf32>(len + 8, cf32{7.0F, 7.0F}));
        std::vector<cf32*> ys;
        for (auto& o : outs) ys.push_back(o.data());
        mix_rows(inputs, coeffs, ys, len);
        for (std::size_t r = 0; r < rows; ++r) {
          for (std::size_t t = len; t < len + 8; ++t) ASSERT_EQ(outs[r][t], cf32(7.0F, 7.0F));
          std::vector<cf32> alone(len);
          mix(inputs, std::span<const cf32>(coeffs).subspan(r * n_in, n_in), alone);
          for (std::size_t t = 0; t < len; ++t) {
            // == on floats: +0 and -0 count as equal, any other difference fails.
            ASSERT_EQ(outs[r][t], alone[t]) << "inputs " << n_in << " rows " << rows << " len "
                                            << len << " row " << r << " t " << t;
          }
        }
      }
    }
  }
}

TEST(Mixer, MixRowsMatchesTheReferenceSum) {
  // mix_rows against std::complex<double> directly, not only against mix().
  constexpr std::size_t kIn = 33, kRows = 6, kLen = 77;
  std::vector<std::vector<cf32>> x(kIn, std::vector<cf32>(kLen));
  std::vector<const cf32*> inputs;
  for (std::size_t i = 0; i < kIn; ++i) {
    for (std::size_t t = 0; t < kLen; ++t) {
      x[i][t] =
          cf32{std::sin(static_cast<float>(5 * t + i)), std::cos(static_cast<float>(t + 3 * i))};
    }
    inputs.push_back(x[i].data());
  }
  std::vector<cf32> coeffs(kRows * kIn);
  for (std::size_t k = 0; k < coeffs.size(); ++k) {
    coeffs[k] = cf32{0.01F * static_cast<float>(k % 13), -0.02F * static_cast<float>(k % 5)};
  }
  std::vector<std::vector<cf32>> outs(kRows, std::vector<cf32>(kLen));
  std::vector<cf32*> ys;
  for (auto& o : outs) ys.push_back(o.data());
  mix_rows(inputs, coeffs, ys, kLen);
  for (std::size_t r = 0; r < kRows; ++r) {
    for (std::size_t t = 0; t < kLen; ++t) {
      std::complex<double> want = 0.0;
      for (std::size_t i = 0; i < kIn; ++i) {
        want += std::complex<double>(coeffs[r * kIn + i]) * std::complex<double>(x[i][t]);
      }
      EXPECT_NEAR(outs[r][t].real(), want.real(), 1e-5) << "row " << r << " t " << t;
      EXPECT_NEAR(outs[r][t].imag(), want.imag(), 1e-5) << "row " << r << " t " << t;
    }
  }
}

TEST(Mixer, RampedCoefficientsAddTheirLinearInterpolationToTheOutput) {
  // Two inputs whose coefficients ramp from `start` by `step` per sample,
  // added onto an output that already holds something. Lengths around the
  // kernel's 48-sample block and its masked tails.
  for (const std::size_t n : {1u, 5u, 8u, 37u, 48u, 49u, 100u, 250u}) {
    std::vector<cf32> x0(n), x1(n), out(n, cf32{0.5F, -0.25F});
    for (std::size_t t = 0; t < n; ++t) {
      const auto tf = static_cast<float>(t);
      x0[t] = {std::cos(0.3F * tf), std::sin(0.3F * tf)};
      x1[t] = {0.01F * tf, -1.0F};
    }
    const std::array<const cf32*, 2> inputs{x0.data(), x1.data()};
    const std::array<cf32, 2> start{cf32{1.0F, 0.0F}, cf32{0.0F, 2.0F}};
    const std::array<cf32, 2> step{cf32{-0.001F, 0.002F}, cf32{0.003F, 0.0F}};
    mix_ramped_add(inputs, start, step, out);
    for (std::size_t t = 0; t < n; ++t) {
      const std::complex<double> c0 =
          std::complex<double>(1.0, 0.0) + double(t) * std::complex<double>(-0.001, 0.002);
      const std::complex<double> c1 =
          std::complex<double>(0.0, 2.0) + double(t) * std::complex<double>(0.003, 0.0);
      const std::complex<double> want = std::complex<double>(0.5, -0.25) +
                                        c0 * std::complex<double>(x0[t]) +
                                        c1 * std::complex<double>(x1[t]);
      EXPECT_NEAR(out[t].real(), want.real(), 1e-4) << "n " << n << " t " << t;
      EXPECT_NEAR(out[t].imag(), want.imag(), 1e-4) << "n " << n << " t " << t;
    }
    // Past the span nothing is touched (the masked tail writes only its samples).
    std::vector<cf32> guarded(n + 8, cf32{9.0F, 9.0F});
    mix_ramped_add(inputs, start, step, std::span<cf32>(guarded).first(n));
    for (std::size_t t = n; t < n + 8; ++t) EXPECT_EQ(guarded[t], cf32(9.0F, 9.0F)) << t;
  }
}

}  // namespace
}  // namespace rfsitl::channel
