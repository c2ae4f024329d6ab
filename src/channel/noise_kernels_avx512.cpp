// The noise kernel 16 pairs at a time with AVX-512F (see noise_math.hpp).
// Built with -mavx512f -mfma -ffp-contract=off (src/CMakeLists.txt): nothing
// but what noise_math.hpp spells out is fused. Also -Wno-uninitialized: GCC 12
// takes the undefined pass-through operand inside AVX-512F's own intrinsics
// (_mm512_undefined_*, a self-initialised variable) for a use of an
// uninitialised value.
#include <immintrin.h>

#include "noise_kernels.hpp"
#include "noise_math.hpp"

namespace rfsitl::channel::noise_kernels {
namespace {

struct Avx512 {
  using U = __m512i;
  using F = __m512;
  static U set1(std::uint32_t v) { return _mm512_set1_epi32(static_cast<int>(v)); }
  static U add(U a, U b) { return _mm512_add_epi32(a, b); }
  static U sub(U a, U b) { return _mm512_sub_epi32(a, b); }
  static U xor_(U a, U b) { return _mm512_xor_si512(a, b); }
  static U and_(U a, U b) { return _mm512_and_si512(a, b); }
  static U or_(U a, U b) { return _mm512_or_si512(a, b); }
  template <int N>
  static U srl(U a) {
    return _mm512_srli_epi32(a, N);
  }
  template <int N>
  static U sll(U a) {
    return _mm512_slli_epi32(a, N);
  }
  static U gt(U a, U b) { return all_ones_where(_mm512_cmpgt_epi32_mask(a, b)); }
  static U mullo(U a, std::uint32_t m) { return _mm512_mullo_epi32(a, set1(m)); }
  static U mulhi(U a, std::uint32_t m) {
    const U mv = set1(m);
    const U even = _mm512_srli_epi64(_mm512_mul_epu32(a, mv), 32);
    const U odd = _mm512_mul_epu32(_mm512_srli_epi64(a, 32), mv);
    return _mm512_mask_blend_epi32(0xAAAA, even, odd);
  }
  static U lane_index(std::uint32_t first) {
    return _mm512_add_epi32(
        set1(first), _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
  static F to_float(U a) { return _mm512_cvtepu32_ps(a); }
  static F int_to_float(U a) { return _mm512_cvtepi32_ps(a); }
  static F set1f(float v) { return _mm512_set1_ps(v); }
  static F addf(F a, F b) { return _mm512_add_ps(a, b); }
  static F subf(F a, F b) { return _mm512_sub_ps(a, b); }
  static F mulf(F a, F b) { return _mm512_mul_ps(a, b); }
  static F fma(F a, F b, F c) { return _mm512_fmadd_ps(a, b, c); }
  static F divf(F a, F b) { return _mm512_div_ps(a, b); }
  static F sqrtf(F a) { return _mm512_sqrt_ps(a); }
  static U as_u(F a) { return _mm512_castps_si512(a); }
  static F as_f(U a) { return _mm512_castsi512_ps(a); }

  /// All ones in the lanes of `m` (AVX-512DQ's vpmovm2d, from AVX-512F).
  static U all_ones_where(__mmask16 m) { return _mm512_maskz_set1_epi32(m, -1); }

  /// Lanes' (re, im) to 16 interleaved complex samples at `out`.
  static void store(float* out, F re, F im) {
    const U first = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const U second =
        _mm512_setr_epi32(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
    _mm512_storeu_ps(out, _mm512_permutex2var_ps(re, first, im));
    _mm512_storeu_ps(out + 16, _mm512_permutex2var_ps(re, second, im));
  }
};

}  // namespace

void group_avx512(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                  float sigma, float* out) {
  Avx512::F v[4];
  noise_math::group_lanes<Avx512>(group, 0, key, stream, sigma, v);
  Avx512::store(out, v[0], v[1]);
  Avx512::store(out + 32, v[2], v[3]);
}

}  // namespace rfsitl::channel::noise_kernels
