// AVX-512 kernels (see mix_kernels.hpp).
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "mix_kernels.hpp"

namespace rfsitl::channel::kernels {
namespace {

/// Where a block finds input i and its coefficient for row r: `Packed`, the
/// inputs as given and each input's R coefficients side by side (cs[2(iR + r)]);
/// `Indexed`, the inputs idx[i] of xs, their coefficients in rows `stride`
/// floats apart (cs[r stride + 2 idx[i]]), so nothing is copied per call.
template <std::size_t R>
struct Packed {
  const float* const* xs;
  const float* cs;
  const float* x(std::size_t i) const { return xs[i]; }
  const float* c(std::size_t i, std::size_t r) const { return cs + 2 * (i * R + r); }
};
struct Indexed {
  const float* const* xs;
  const std::uint32_t* idx;
  const float* cs;
  std::size_t stride;
  const float* x(std::size_t i) const { return xs[idx[i]]; }
  const float* c(std::size_t i, std::size_t r) const { return cs + r * stride + 2 * idx[i]; }
};

/// Several receivers at once: R rows of coefficients over the same inputs, so
/// each input vector loaded serves R receivers (the GEMM idea: at N >= 32 the
/// inputs outgrow L1 and a one-receiver kernel waits on loads). R * K * 2
/// accumulators.
template <std::size_t R, std::size_t K, typename In>
__attribute__((target("avx512f"), always_inline)) inline void avx512_rows_block(
    const In& in, std::size_t n_in, float* const* __restrict ys, std::size_t t,
    __mmask16 last = 0xFFFF) {
  const __m512 alternate = _mm512_setr_ps(-1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1);
  __m512 a[R][K];
  __m512 b[R][K];
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t k = 0; k < K; ++k) a[r][k] = b[r][k] = _mm512_setzero_ps();
  for (std::size_t i = 0; i < n_in; ++i) {
    const float* __restrict x = in.x(i) + 2 * t;
    __m512 v[K];
    for (std::size_t k = 0; k + 1 < K; ++k) v[k] = _mm512_loadu_ps(x + 16 * k);
    v[K - 1] = _mm512_maskz_loadu_ps(last, x + 16 * (K - 1));  // a tail loads only its samples
    for (std::size_t r = 0; r < R; ++r) {
      const float* c = in.c(i, r);
      const __m512 cr = _mm512_set1_ps(c[0]);
      const __m512 ci = _mm512_set1_ps(c[1]);
      for (std::size_t k = 0; k < K; ++k) {
        a[r][k] = _mm512_fmadd_ps(cr, v[k], a[r][k]);
        b[r][k] = _mm512_fmadd_ps(ci, v[k], b[r][k]);
      }
    }
  }
  for (std::size_t r = 0; r < R; ++r) {
    for (std::size_t k = 0; k < K; ++k) {
      const __m512 swapped = _mm512_shuffle_ps(b[r][k], b[r][k], 0xB1);
      _mm512_mask_storeu_ps(ys[r] + 2 * t + 16 * k, k + 1 == K ? last : __mmask16{0xFFFF},
                            _mm512_fmadd_ps(alternate, swapped, a[r][k]));
    }
  }
}

/// Block::run<vectors>(args...) for a `vectors` known only at run time (J..K):
/// a kernel's last, partial block.
template <typename Block, std::size_t J, std::size_t K, typename... Args>
__attribute__((target("avx512f"), always_inline)) inline void avx512_rest(std::size_t vectors,
                                                                          Args... args) {
  if constexpr (J <= K) {
    if (vectors == J) {
      Block::template run<J>(args...);
    } else {
      avx512_rest<Block, J + 1, K>(vectors, args...);
    }
  }
}

/// The mask of a kernel's last vector, which holds the last 1..8 of n - t
/// samples (two floats each), and how many vectors those n - t samples take.
struct Tail {
  std::size_t vectors;
  __mmask16 last;
};
inline Tail tail_of(std::size_t samples) {
  const std::size_t vectors = (samples + 7) / 8;
  const std::size_t in_last = samples - 8 * (vectors - 1);
  return {vectors, static_cast<__mmask16>((1U << (2 * in_last)) - 1)};
}

template <std::size_t R, typename In>
struct RowsBlock {
  template <std::size_t K>
  __attribute__((target("avx512f"), always_inline)) static void run(const In& in, std::size_t n_in,
                                                                    float* const* ys, std::size_t t,
                                                                    __mmask16 last) {
    avx512_rows_block<R, K>(in, n_in, ys, t, last);
  }
};

template <std::size_t R, typename In>
__attribute__((target("avx512f"))) void rows(const In& in, std::size_t n_in, float* const* ys,
                                             std::size_t n) {
  // As many vectors per row as keep R * K * 2 accumulators and K inputs within
  // the 32 registers.
  constexpr std::size_t K = R == 1 ? 8 : R == 2 ? 6 : R == 3 ? 4 : 3;
  std::size_t t = 0;
  for (; t + 8 * K <= n; t += 8 * K) avx512_rows_block<R, K>(in, n_in, ys, t);
  if (t == n) return;
  // The rest (fewer than 8 K samples) in one more pass over the inputs, its last
  // vector masked to the samples that exist.
  const Tail tail = tail_of(n - t);
  avx512_rest<RowsBlock<R, In>, 1, K>(tail.vectors, in, n_in, ys, t, tail.last);
}

/// The fading mixer's block: coefficients ramp per sample, c_i(t) = c0_i + t
/// d_i, computed in the lanes (one FMA each for re and im), then summed as in
/// the flat kernel and added to y once per block.
struct RampedBlock {
  template <std::size_t K>
  __attribute__((target("avx512f"), always_inline)) static void run(
      const float* const* __restrict xs, const float* __restrict c0, const float* __restrict d,
      std::size_t n_in, float* __restrict y, std::size_t t, __mmask16 last) {
    const __m512 alternate = _mm512_setr_ps(-1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1);
    const __m512 pairs = _mm512_setr_ps(0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7);
    __m512 time[K];
    __m512 a[K];
    __m512 b[K];
    for (std::size_t k = 0; k < K; ++k) {
      time[k] = _mm512_add_ps(pairs, _mm512_set1_ps(static_cast<float>(t + 8 * k)));
      a[k] = b[k] = _mm512_setzero_ps();
    }
    for (std::size_t i = 0; i < n_in; ++i) {
      const float* __restrict x = xs[i] + 2 * t;
      const __m512 c0r = _mm512_set1_ps(c0[2 * i]);
      const __m512 c0i = _mm512_set1_ps(c0[2 * i + 1]);
      const __m512 dr = _mm512_set1_ps(d[2 * i]);
      const __m512 di = _mm512_set1_ps(d[2 * i + 1]);
      for (std::size_t k = 0; k < K; ++k) {
        const __m512 v =
            k + 1 < K ? _mm512_loadu_ps(x + 16 * k) : _mm512_maskz_loadu_ps(last, x + 16 * k);
        a[k] = _mm512_fmadd_ps(_mm512_fmadd_ps(time[k], dr, c0r), v, a[k]);
        b[k] = _mm512_fmadd_ps(_mm512_fmadd_ps(time[k], di, c0i), v, b[k]);
      }
    }
    for (std::size_t k = 0; k < K; ++k) {
      const __mmask16 m = k + 1 == K ? last : __mmask16{0xFFFF};
      const __m512 sum = _mm512_fmadd_ps(alternate, _mm512_shuffle_ps(b[k], b[k], 0xB1), a[k]);
      float* out = y + 2 * t + 16 * k;
      _mm512_mask_storeu_ps(out, m, _mm512_add_ps(_mm512_maskz_loadu_ps(m, out), sum));
    }
  }
};

}  // namespace

__attribute__((target("avx512f"))) void mix_ramped_avx512(const float* const* xs, const float* c0,
                                                          const float* d, std::size_t n_in,
                                                          float* y, std::size_t n) {
  constexpr std::size_t K = 6;  // 12 accumulators, 6 times, 4 coefficients, inputs
  std::size_t t = 0;
  for (; t + 8 * K <= n; t += 8 * K) RampedBlock::run<K>(xs, c0, d, n_in, y, t, 0xFFFF);
  if (t == n) return;
  const Tail tail = tail_of(n - t);
  avx512_rest<RampedBlock, 1, K>(tail.vectors, xs, c0, d, n_in, y, t, tail.last);
}
void mix_avx512(const float* const* xs, const float* cs, std::size_t n_in, float* y,
                std::size_t n) {
  float* const ys[1] = {y};
  rows<1>(Packed<1>{xs, cs}, n_in, ys, n);
}

__attribute__((target("avx512f"))) std::size_t nonzero_columns_avx512(
    const float* cs, std::size_t stride, std::size_t rows_, std::size_t n_in, std::uint32_t* idx) {
  // Eight inputs (16 floats) of every row per step: a bit per float that is not
  // zero, then one per input (its re or its im), in input order.
  const __m512 zero = _mm512_setzero_ps();
  std::size_t k = 0;
  for (std::size_t i = 0; i < n_in; i += 8) {
    const std::size_t here = std::min<std::size_t>(8, n_in - i);
    const auto mask = static_cast<__mmask16>((1U << (2 * here)) - 1);
    std::uint32_t bits = 0;
    for (std::size_t r = 0; r < rows_; ++r) {
      const __m512 c = _mm512_maskz_loadu_ps(mask, cs + r * stride + 2 * i);
      bits |= _mm512_cmp_ps_mask(c, zero, _CMP_NEQ_UQ);
    }
    bits |= bits >> 1;
    for (std::size_t j = 0; j < here; ++j) {
      idx[k] = static_cast<std::uint32_t>(i + j);
      k += (bits >> (2 * j)) & 1U;
    }
  }
  return k;
}

void mix_rows_avx512(const float* const* xs, const std::uint32_t* idx, std::size_t n_idx,
                     const float* cs, std::size_t stride, std::size_t rows_, float* const* ys,
                     std::size_t n) {
  const Indexed in{xs, idx, cs, stride};
  switch (rows_) {
    case 4:
      rows<4>(in, n_idx, ys, n);
      break;
    case 3:
      rows<3>(in, n_idx, ys, n);
      break;
    case 2:
      rows<2>(in, n_idx, ys, n);
      break;
    default:
      rows<1>(in, n_idx, ys, n);
      break;
  }
}

}  // namespace rfsitl::channel::kernels
