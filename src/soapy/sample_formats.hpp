#pragma once
/// The stream formats the module offers and their conversion to and from the
/// module's cf32 samples. One digital full scale for all: 1.0 in CF32 (the
/// native format), 32767 in CS16, 127 in CS8; the gains map the emulator's
/// units onto it (signal_path.hpp). Integer conversions round and saturate,
/// so a loud signal clips instead of wrapping.
#include <SoapySDR/Formats.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::soapy {

enum class SampleFormat { kCF32, kCS16, kCS8 };

inline const std::vector<std::string>& format_names() {
  static const std::vector<std::string> names = {SOAPY_SDR_CF32, SOAPY_SDR_CS16, SOAPY_SDR_CS8};
  return names;
}

/// Throws std::runtime_error naming the formats offered.
inline SampleFormat format_of(const std::string& name) {
  if (name == SOAPY_SDR_CF32) return SampleFormat::kCF32;
  if (name == SOAPY_SDR_CS16) return SampleFormat::kCS16;
  if (name == SOAPY_SDR_CS8) return SampleFormat::kCS8;
  throw std::runtime_error("rfsitl: stream format '" + name + "' is not offered (CF32, CS16, CS8)");
}

namespace detail {

template <typename T>
void to_ints(std::span<const cf32> in, void* out, float scale) {
  auto* o = static_cast<T*>(out);
  const auto lo = static_cast<float>(std::numeric_limits<T>::min());
  const auto hi = static_cast<float>(std::numeric_limits<T>::max());
  auto conv = [&](float v) { return static_cast<T>(std::clamp(std::round(v * scale), lo, hi)); };
  for (std::size_t i = 0; i < in.size(); ++i) {
    o[2 * i] = conv(in[i].real());
    o[2 * i + 1] = conv(in[i].imag());
  }
}

template <typename T>
void from_ints(const void* in, std::span<cf32> out, float scale) {
  const auto* p = static_cast<const T*>(in);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = cf32(static_cast<float>(p[2 * i]) / scale, static_cast<float>(p[2 * i + 1]) / scale);
  }
}

}  // namespace detail

/// Writes in.size() samples of `format` to `out` (the caller's buffer).
inline void convert_out(std::span<const cf32> in, SampleFormat format, void* out) {
  switch (format) {
    case SampleFormat::kCF32:
      std::copy(in.begin(), in.end(), static_cast<cf32*>(out));
      break;
    case SampleFormat::kCS16:
      detail::to_ints<std::int16_t>(in, out, 32767.0F);
      break;
    case SampleFormat::kCS8:
      detail::to_ints<std::int8_t>(in, out, 127.0F);
      break;
  }
}

/// Reads out.size() samples of `format` from `in` (the caller's buffer).
inline void convert_in(const void* in, SampleFormat format, std::span<cf32> out) {
  switch (format) {
    case SampleFormat::kCF32:
      std::copy_n(static_cast<const cf32*>(in), out.size(), out.begin());
      break;
    case SampleFormat::kCS16:
      detail::from_ints<std::int16_t>(in, out, 32767.0F);
      break;
    case SampleFormat::kCS8:
      detail::from_ints<std::int8_t>(in, out, 127.0F);
      break;
  }
}

}  // namespace rfsitl::soapy
