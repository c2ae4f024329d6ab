// The noise kernel 8 pairs at a time with AVX2 and FMA (see noise_math.hpp).
// Built with -mavx2 -mfma -ffp-contract=off (src/CMakeLists.txt): nothing but
// what noise_math.hpp spells out is fused.
#include <immintrin.h>

#include "noise_kernels.hpp"
#include "noise_math.hpp"

namespace rfsitl::channel::noise_kernels {
namespace {

struct Avx2 {
  using U = __m256i;
  using F = __m256;
  static U set1(std::uint32_t v) { return _mm256_set1_epi32(static_cast<int>(v)); }
  static U add(U a, U b) { return _mm256_add_epi32(a, b); }
  static U sub(U a, U b) { return _mm256_sub_epi32(a, b); }
  static U xor_(U a, U b) { return _mm256_xor_si256(a, b); }
  static U and_(U a, U b) { return _mm256_and_si256(a, b); }
  static U or_(U a, U b) { return _mm256_or_si256(a, b); }
  template <int N>
  static U srl(U a) {
    return _mm256_srli_epi32(a, N);
  }
  template <int N>
  static U sll(U a) {
    return _mm256_slli_epi32(a, N);
  }
  static U gt(U a, U b) { return _mm256_cmpgt_epi32(a, b); }
  static U mullo(U a, std::uint32_t m) { return _mm256_mullo_epi32(a, set1(m)); }
  static U mulhi(U a, std::uint32_t m) {
    // 32 x 32 -> 64 of the even lanes, then of the odd ones moved down; the
    // high words go back to their lanes.
    const U mv = set1(m);
    const U even = _mm256_srli_epi64(_mm256_mul_epu32(a, mv), 32);
    const U odd = _mm256_mul_epu32(_mm256_srli_epi64(a, 32), mv);
    return _mm256_blend_epi32(even, odd, 0xAA);
  }
  static U lane_index(std::uint32_t first) {
    return _mm256_add_epi32(set1(first), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  }
  static F to_float(U a) {
    // AVX2 converts signed words only: the two 16-bit halves convert exactly,
    // and their sum rounds once, as a correctly rounded conversion does.
    const F hi = _mm256_cvtepi32_ps(_mm256_srli_epi32(a, 16));
    const F lo = _mm256_cvtepi32_ps(_mm256_and_si256(a, set1(0xFFFFU)));
    return _mm256_add_ps(_mm256_mul_ps(hi, set1f(65536.0F)), lo);
  }
  static F int_to_float(U a) { return _mm256_cvtepi32_ps(a); }
  static F set1f(float v) { return _mm256_set1_ps(v); }
  static F addf(F a, F b) { return _mm256_add_ps(a, b); }
  static F subf(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mulf(F a, F b) { return _mm256_mul_ps(a, b); }
  static F fma(F a, F b, F c) { return _mm256_fmadd_ps(a, b, c); }
  static F divf(F a, F b) { return _mm256_div_ps(a, b); }
  static F sqrtf(F a) { return _mm256_sqrt_ps(a); }
  static U as_u(F a) { return _mm256_castps_si256(a); }
  static F as_f(U a) { return _mm256_castsi256_ps(a); }

  /// Lanes' (re, im) to 8 interleaved complex samples at `out`.
  static void store(float* out, F re, F im) {
    const F lo = _mm256_unpacklo_ps(re, im);  // samples 0 1 | 4 5
    const F hi = _mm256_unpackhi_ps(re, im);  // samples 2 3 | 6 7
    _mm256_storeu_ps(out, _mm256_permute2f128_ps(lo, hi, 0x20));
    _mm256_storeu_ps(out + 8, _mm256_permute2f128_ps(lo, hi, 0x31));
  }
};

}  // namespace

void group_avx2(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                float sigma, float* out) {
  for (std::uint32_t first = 0; first < 16; first += 8) {
    Avx2::F v[4];
    noise_math::group_lanes<Avx2>(group, first, key, stream, sigma, v);
    Avx2::store(out + 2 * first, v[0], v[1]);
    Avx2::store(out + 2 * (16 + first), v[2], v[3]);
  }
}

}  // namespace rfsitl::channel::noise_kernels
