#pragma once
/// The receiver kernels written once over a vector of W floats (GCC's vector
/// extensions) and compiled once per instruction set: receiver_kernels.cpp
/// (W = 1, the reference, and W = 4, SSE2, which every x86-64 has),
/// receiver_kernels_avx2.cpp (W = 8) and receiver_kernels_avx512.cpp (W = 16).
/// Included only by those files; internal linkage, so that the copies built
/// with different instruction sets never merge at link time.
///
/// Bit-identity across W: each vector lane holds one output and goes through
/// that output's scalar sequence of operations; the files are compiled with
/// -ffp-contract=off so that no multiply and add fuse.
#include <cstddef>
#include <cstring>
#include <type_traits>

#include "receiver_kernels.hpp"

namespace rfsitl::phy::gmsk {

/// The versions built with -mavx2 and -mavx512f; call only where the CPU has them.
const ReceiverKernels& avx2_kernels();
const ReceiverKernels& avx512_kernels();

namespace {

// GCC ignores vector_size on an alias template with a dependent size, hence
// one named type per width.
typedef float Vec1 __attribute__((vector_size(4)));
typedef float Vec4 __attribute__((vector_size(16)));
typedef float Vec8 __attribute__((vector_size(32)));
typedef float Vec16 __attribute__((vector_size(64)));

/// W floats, one output per lane.
template <std::size_t W>
using Vec =
    std::conditional_t<W == 1, Vec1,
                       std::conditional_t<W == 4, Vec4, std::conditional_t<W == 8, Vec8, Vec16>>>;

template <std::size_t W>
Vec<W> load(const float* p) {
  Vec<W> v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <std::size_t W>
void store(float* p, Vec<W> v) {
  std::memcpy(p, &v, sizeof v);
}

/// Outputs out[j .. j + W) of ReceiverKernels::matched_filter.
template <std::size_t W>
void filter_block(const float* in, const float* taps, std::size_t len, float* out) {
  Vec<W> acc{};
  for (std::size_t i = 0; i < len; ++i) acc += taps[i] * load<W>(in + 2 * i);
  store<W>(out, acc);
}

template <std::size_t W>
void matched_filter(const float* in, const float* taps, std::size_t len, std::size_t n,
                    float* out) {
  std::size_t j = 0;
  for (; j + W <= n; j += W) filter_block<W>(in + j, taps, len, out + j);
  for (; j < n; ++j) filter_block<1>(in + j, taps, len, out + j);
}

/// Outputs m .. m + W of ReceiverKernels::correlate (x and y already at m).
template <std::size_t W>
void correlate_block(const float* x, const float* y, std::size_t stride, const float* rr,
                     const float* ri, float* c_re, float* c_im, float* energy) {
  constexpr std::size_t kTaps = 32;
  constexpr std::size_t kLanes = 8;
  Vec<W> cr{};
  Vec<W> ci{};
  Vec<W> en{};
  for (std::size_t l = 0; l < kLanes; ++l) {
    Vec<W> ar{};
    Vec<W> ai{};
    Vec<W> ae{};
    for (std::size_t i = l; i < kTaps; i += kLanes) {
      const Vec<W> xv = load<W>(x + i * stride);
      const Vec<W> yv = load<W>(y + i * stride);
      ar += rr[i] * xv - ri[i] * yv;
      ai += rr[i] * yv + ri[i] * xv;
      ae += xv * xv + yv * yv;
    }
    cr += ar;
    ci += ai;
    en += ae;
  }
  store<W>(c_re, cr);
  store<W>(c_im, ci);
  store<W>(energy, en);
}

template <std::size_t W>
void correlate(const float* x, const float* y, std::size_t stride, const float* rr, const float* ri,
               std::size_t n, float* c_re, float* c_im, float* energy) {
  std::size_t m = 0;
  for (; m + W <= n; m += W) {
    correlate_block<W>(x + m, y + m, stride, rr, ri, c_re + m, c_im + m, energy + m);
  }
  for (; m < n; ++m) {
    correlate_block<1>(x + m, y + m, stride, rr, ri, c_re + m, c_im + m, energy + m);
  }
}

template <std::size_t W>
constexpr ReceiverKernels kernels_of(const char* name) {
  return ReceiverKernels{name, &matched_filter<W>, &correlate<W>};
}

}  // namespace
}  // namespace rfsitl::phy::gmsk
