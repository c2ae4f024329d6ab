#include "code_correlator.hpp"

#include <cstring>

namespace rfsitl::phy::dsss {
namespace {

// Outputs per tile: 16 complex = 32 floats. The accumulators are GCC vector
// extension values, which GCC keeps in registers across the chip loop (with a
// plain float array it reloads and stores them for every chip): eight 4-float
// vectors for baseline x86-64 (SSE, 16 registers), four 8-float vectors in the
// AVX2 variant, picked at run time on CPUs that have AVX2.
constexpr std::size_t kTile = 16;
constexpr std::size_t kTileFloats = 2 * kTile;
typedef float Vec4 __attribute__((vector_size(16)));
typedef float Vec8 __attribute__((vector_size(32)));

using TileFunction = void (*)(const float*, const std::size_t*, std::size_t, const std::size_t*,
                              std::size_t, float*);

/// One tile: acc = sum of the `plus` windows minus the `minus` windows, then
/// power = |acc|^2 per complex output.
template <typename V>
[[gnu::always_inline]] inline void tile_kernel(const float* y, const std::size_t* plus,
                                               std::size_t plus_count, const std::size_t* minus,
                                               std::size_t minus_count, float* power) {
  constexpr std::size_t kLanes = sizeof(V) / sizeof(float);
  constexpr std::size_t kVecs = kTileFloats / kLanes;
  V acc[kVecs] = {};
  for (std::size_t t = 0; t < plus_count; ++t) {
    const float* s = y - plus[t];
#pragma GCC unroll 8
    for (std::size_t v = 0; v < kVecs; ++v) {
      V x;
      std::memcpy(&x, s + v * kLanes, sizeof x);  // unaligned load
      acc[v] += x;
    }
  }
  for (std::size_t t = 0; t < minus_count; ++t) {
    const float* s = y - minus[t];
#pragma GCC unroll 8
    for (std::size_t v = 0; v < kVecs; ++v) {
      V x;
      std::memcpy(&x, s + v * kLanes, sizeof x);
      acc[v] -= x;
    }
  }
  float out[kTileFloats];
  std::memcpy(out, acc, sizeof out);
  for (std::size_t j = 0; j < kTile; ++j) {
    power[j] = out[2 * j] * out[2 * j] + out[2 * j + 1] * out[2 * j + 1];
  }
}

void tile_baseline(const float* y, const std::size_t* plus, std::size_t plus_count,
                   const std::size_t* minus, std::size_t minus_count, float* power) {
  tile_kernel<Vec4>(y, plus, plus_count, minus, minus_count, power);
}

#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("avx2"))) void tile_avx2(const float* y, const std::size_t* plus,
                                               std::size_t plus_count, const std::size_t* minus,
                                               std::size_t minus_count, float* power) {
  tile_kernel<Vec8>(y, plus, plus_count, minus, minus_count, power);
}
#endif

TileFunction best_tile_function() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();  // may run before libgcc's own initializer
  if (__builtin_cpu_supports("avx2")) return tile_avx2;
#endif
  return tile_baseline;
}

const TileFunction kBestTileFunction = best_tile_function();

}  // namespace

CodeCorrelator::CodeCorrelator(std::span<const Chip> chips, unsigned samples_per_chip,
                               Kernel kernel)
    : length_(chips.size()),
      samples_per_chip_(samples_per_chip),
      portable_(kernel == Kernel::kPortable) {
  for (std::size_t i = 0; i < length_; ++i) {
    const std::size_t back = 2 * (length_ - 1 - i) * samples_per_chip_;
    (chips[i] > 0 ? plus_ : minus_).push_back(back);
  }
}

cf32 CodeCorrelator::correlate(const cf32* y) const {
  const auto* f = reinterpret_cast<const float*>(y);
  float re = 0.0F;
  float im = 0.0F;
  for (const std::size_t b : plus_) {
    const float* s = f - b;
    re += s[0];
    im += s[1];
  }
  for (const std::size_t b : minus_) {
    const float* s = f - b;
    re -= s[0];
    im -= s[1];
  }
  return {re, im};
}

void CodeCorrelator::correlate_power(const cf32* y, std::size_t count, float* power) const {
  const TileFunction tile = portable_ ? tile_baseline : kBestTileFunction;
  std::size_t j = 0;
  for (; j + kTile <= count; j += kTile) {
    tile(reinterpret_cast<const float*>(y + j), plus_.data(), plus_.size(), minus_.data(),
         minus_.size(), power + j);
  }
  for (; j < count; ++j) power[j] = std::norm(correlate(y + j));
}

}  // namespace rfsitl::phy::dsss
