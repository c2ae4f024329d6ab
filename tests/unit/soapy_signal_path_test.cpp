// The SoapySDR module's sample handling without an emulator: format
// conversions (sample_formats.hpp), the frequency offset and gain applied to
// each direction, and the gain's mapping onto the formats' one full scale
// (signal_path.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "sample_formats.hpp"
#include "signal_path.hpp"

namespace rfsitl::soapy {
namespace {

std::vector<cf32> ramp(std::size_t n, float peak) {
  std::vector<cf32> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float x = peak * (2.0F * static_cast<float>(i) / static_cast<float>(n - 1) - 1.0F);
    v[i] = {x, -0.5F * x};
  }
  return v;
}

template <typename T>
void expect_round_trip(SampleFormat f, float full_scale) {
  const auto in = ramp(101, 1.0F);
  std::vector<T> wire(2 * in.size());
  convert_out(in, f, wire.data());
  std::vector<cf32> back(in.size());
  convert_in(wire.data(), f, back);
  for (std::size_t i = 0; i < in.size(); ++i) {
    // Rounding: at most half a step of the integer format.
    EXPECT_NEAR(back[i].real(), in[i].real(), 0.5F / full_scale + 1e-6F) << i;
    EXPECT_NEAR(back[i].imag(), in[i].imag(), 0.5F / full_scale + 1e-6F) << i;
  }
}

TEST(SoapySampleFormats, IntegerFormatsRoundTripWithinHalfAStep) {
  expect_round_trip<std::int16_t>(SampleFormat::kCS16, 32767.0F);
  expect_round_trip<std::int8_t>(SampleFormat::kCS8, 127.0F);
}

TEST(SoapySampleFormats, LoudSamplesClipInsteadOfWrapping) {
  const std::vector<cf32> in = {{2.0F, -2.0F}, {1.5F, 0.25F}};
  std::vector<std::int16_t> s16(4);
  convert_out(in, SampleFormat::kCS16, s16.data());
  EXPECT_EQ(s16, (std::vector<std::int16_t>{32767, -32768, 32767, 8192}));
  std::vector<std::int8_t> s8(4);
  convert_out(in, SampleFormat::kCS8, s8.data());
  EXPECT_EQ(s8, (std::vector<std::int8_t>{127, -128, 127, 32}));
}

TEST(SoapySampleFormats, Cf32IsCopiedUnchanged) {
  const auto in = ramp(8, 3.0F);  // beyond full scale: CF32 does not clip
  std::vector<cf32> out(in.size());
  convert_out(in, SampleFormat::kCF32, out.data());
  EXPECT_EQ(out, in);
  std::vector<cf32> back(in.size());
  convert_in(out.data(), SampleFormat::kCF32, back);
  EXPECT_EQ(back, in);
}

TEST(SoapySampleFormats, UnknownFormatIsRefusedByName) {
  EXPECT_EQ(format_of("CS16"), SampleFormat::kCS16);
  try {
    format_of("CU8");
    FAIL() << "CU8 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'CU8' is not offered"), std::string::npos);
  }
}

TEST(SoapySignalPath, GainScalesTheAmplitudeAndOutOfBandSilences) {
  EXPECT_DOUBLE_EQ(amplitude_of({true, 0.0, 0.0}), 1.0);
  EXPECT_NEAR(amplitude_of({true, 0.0, -20.0}), 0.1, 1e-12);
  EXPECT_NEAR(amplitude_of({true, 0.0, 6.0}), 1.9953, 1e-4);
  EXPECT_EQ(amplitude_of({false, 0.0, 6.0}), 0.0);
  std::vector<cf32> s(4, cf32{0.5F, -0.25F});
  shift_and_scale(s, 123, 0.0, 0.1);
  for (const auto& x : s) {
    EXPECT_NEAR(x.real(), 0.05F, 1e-7F);
    EXPECT_NEAR(x.imag(), -0.025F, 1e-7F);
  }
}

TEST(SoapySignalPath, OffsetPhaseIsContinuousAcrossChunksAndFollowsAbsoluteTime) {
  // A constant shifted in chunks of uneven sizes equals the same constant
  // shifted at once: the phase depends on the absolute time only.
  const double f = 0.0123;  // cycles per sample
  const SampleTime t0 = 1'000'000'007;
  std::vector<cf32> whole(1000, cf32{1.0F, 0.0F});
  shift_and_scale(whole, t0, f, 1.0);
  std::vector<cf32> pieces(whole.size(), cf32{1.0F, 0.0F});
  std::size_t at = 0;
  for (std::size_t len : {1U, 250U, 7U, 742U}) {
    shift_and_scale(std::span<cf32>(pieces).subspan(at, len), t0 + static_cast<SampleTime>(at), f,
                    1.0);
    at += len;
  }
  ASSERT_EQ(at, whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_NEAR(std::abs(pieces[i] - whole[i]), 0.0F, 1e-5F) << i;
    const double expected = 2.0 * std::numbers::pi * f * static_cast<double>(t0 + i);
    EXPECT_NEAR(
        std::abs(whole[i] - cf32(std::polar(1.0, std::fmod(expected, 2 * std::numbers::pi)))), 0.0F,
        1e-4F)
        << i;
  }
}

TEST(SoapySignalPath, TxShiftThenRxShiftOfTheSameOffsetRestoresTheSamples) {
  // What one node tuned +f above the carrier sends, another tuned +f hears
  // unchanged: the module shifts TX by +f and RX by -f.
  const auto in = ramp(64, 0.8F);
  auto s = in;
  shift_and_scale(s, 5000, 0.2, 1.0);
  shift_and_scale(s, 5000, -0.2, 1.0);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(std::abs(s[i] - in[i]), 0.0F, 1e-5F);
}

TEST(SoapyGain, OutOfRangeSettingsAreClampedIntoTheRange) {
  for (const GainControl& g : {kRxGain, kTxGain}) {
    EXPECT_EQ(g.clamp(g.min_db - 100.0), g.min_db);
    EXPECT_EQ(g.clamp(g.max_db + 100.0), g.max_db);
    const double inside = 0.5 * (g.min_db + g.max_db);
    EXPECT_EQ(g.clamp(inside), inside);
    EXPECT_TRUE(std::isnan(g.clamp(std::nan(""))));
    EXPECT_EQ(g.clamp(g.default_db), g.default_db) << "the default lies in the range";
  }
}

TEST(SoapyGain, UnitySettingPassesTheEmulatorsUnitsUnchanged) {
  for (const GainControl& g : {kRxGain, kTxGain}) {
    ASSERT_EQ(g.clamp(g.unity_db), g.unity_db) << "reachable";
    EXPECT_EQ(amplitude_of({true, 0.0, g.scale_db(g.unity_db)}), 1.0);
    // Each dB of setting is a dB of level.
    EXPECT_NEAR(amplitude_of({true, 0.0, g.scale_db(g.unity_db - 20.0)}), 0.1, 1e-12);
  }
}

/// `n` samples of complex Gaussian noise of unit power (the emulator's
/// receiver noise in its native units), seeded.
std::vector<cf32> unit_noise(std::size_t n) {
  std::mt19937 rng(7);
  std::normal_distribution<float> half(0.0F, std::sqrt(0.5F));
  std::vector<cf32> v(n);
  for (auto& x : v) x = {half(rng), half(rng)};
  return v;
}

/// The RMS of the integers of `w` (I and Q alike), and the fraction at either end.
template <typename T>
std::pair<double, double> rms_and_clipped(const std::vector<T>& w) {
  double sum = 0.0;
  std::size_t clipped = 0;
  for (const T v : w) {
    sum += static_cast<double>(v) * static_cast<double>(v);
    clipped += v == std::numeric_limits<T>::max() || v == std::numeric_limits<T>::min() ? 1U : 0U;
  }
  return {std::sqrt(sum / static_cast<double>(w.size())),
          static_cast<double>(clipped) / static_cast<double>(w.size())};
}

TEST(SoapyGain, DefaultRxGainPutsTheNoiseInTheLowBitsOfCs16WithoutClipping) {
  auto s = unit_noise(100'000);
  shift_and_scale(s, 0, 0.0, amplitude_of({true, 0.0, kRxGain.scale_db(kRxGain.default_db)}));
  std::vector<std::int16_t> wire(2 * s.size());
  convert_out(s, SampleFormat::kCS16, wire.data());
  const auto [rms, clipped] = rms_and_clipped(wire);
  // A real SDR's noise floor: a few bits above the last, far below full scale.
  EXPECT_GE(rms, 8.0);
  EXPECT_LE(rms, 64.0);
  EXPECT_EQ(clipped, 0.0);
}

TEST(SoapyGain, EveryFormatSharesOneFullScale) {
  // What a gain makes of a sample is one value, whatever the format carries:
  // CF32 v == CS16 v * 32767 == CS8 v * 127, within rounding.
  auto s = ramp(255, 1.0F);
  shift_and_scale(s, 0, 0.0, amplitude_of({true, 0.0, kRxGain.scale_db(kRxGain.unity_db - 3.0)}));
  std::vector<cf32> f32(s.size());
  std::vector<std::int16_t> s16(2 * s.size());
  std::vector<std::int8_t> s8(2 * s.size());
  convert_out(s, SampleFormat::kCF32, f32.data());
  convert_out(s, SampleFormat::kCS16, s16.data());
  convert_out(s, SampleFormat::kCS8, s8.data());
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_NEAR(s16[2 * i] / 32767.0, f32[i].real(), 0.5 / 32767.0 + 1e-6) << i;
    EXPECT_NEAR(s8[2 * i + 1] / 127.0, f32[i].imag(), 0.5 / 127.0 + 1e-6) << i;
  }
}

}  // namespace
}  // namespace rfsitl::soapy
