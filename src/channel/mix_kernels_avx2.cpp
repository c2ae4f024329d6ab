// AVX2 + FMA kernels (see mix_kernels.hpp).
#include <immintrin.h>

#include "mix_kernels.hpp"

namespace rfsitl::channel::kernels {
namespace {

template <std::size_t K>
__attribute__((target("avx2,fma"), always_inline)) inline void avx2_block(
    const float* const* __restrict xs, const float* __restrict cs, std::size_t n_in,
    float* __restrict y, std::size_t t) {
  const __m256 alternate = _mm256_setr_ps(-1, 1, -1, 1, -1, 1, -1, 1);
  __m256 a[K];
  __m256 b[K];
  for (std::size_t k = 0; k < K; ++k) a[k] = b[k] = _mm256_setzero_ps();
  for (std::size_t i = 0; i < n_in; ++i) {
    const float* __restrict x = xs[i] + 2 * t;
    const __m256 cr = _mm256_set1_ps(cs[2 * i]);
    const __m256 ci = _mm256_set1_ps(cs[2 * i + 1]);
    for (std::size_t k = 0; k < K; ++k) {
      const __m256 v = _mm256_loadu_ps(x + 8 * k);
      a[k] = _mm256_fmadd_ps(cr, v, a[k]);
      b[k] = _mm256_fmadd_ps(ci, v, b[k]);
    }
  }
  for (std::size_t k = 0; k < K; ++k) {
    const __m256 swapped = _mm256_shuffle_ps(b[k], b[k], 0xB1);
    _mm256_storeu_ps(y + 2 * t + 8 * k, _mm256_fmadd_ps(alternate, swapped, a[k]));
  }
}

}  // namespace

__attribute__((target("avx2,fma"))) void mix_avx2(const float* const* __restrict xs,
                                                  const float* __restrict cs, std::size_t n_in,
                                                  float* __restrict y, std::size_t n) {
  std::size_t t = 0;
  for (; t + 24 <= n; t += 24) avx2_block<6>(xs, cs, n_in, y, t);
  for (; t + 4 <= n; t += 4) avx2_block<1>(xs, cs, n_in, y, t);
  if (t < n) {
    const float* rest[kMaxGroup];
    for (std::size_t i = 0; i < n_in; ++i) rest[i] = xs[i] + 2 * t;
    mix_scalar(rest, cs, n_in, y + 2 * t, n - t);
  }
}

}  // namespace rfsitl::channel::kernels
