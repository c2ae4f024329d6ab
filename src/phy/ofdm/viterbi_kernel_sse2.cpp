// The SSE2 add-compare-select kernel, for x86-64 CPUs without AVX2 (SSE2 is
// part of the x86-64 baseline, so no target attribute is needed). The 64 int16
// metrics live in eight registers in state order (M[k] = states 8k ... 8k + 7);
// (M[k], M[k + 4]) are lane-aligned butterflies whose even and odd results
// unpack straight back into state order. Same arithmetic as acs_portable.
#if defined(__SSE2__)
#include <emmintrin.h>

#include <array>

#include "viterbi_kernels.hpp"

namespace rfsitl::phy::ofdm::viterbi {
namespace {

__m128i load(const std::int16_t* p) {
  return _mm_load_si128(reinterpret_cast<const __m128i*>(p));
}

/// The maximum of the eight registers' 64 metrics, in every lane.
__m128i max_all(const __m128i* m) {
  __m128i x = m[0];
  for (std::size_t k = 1; k < 8; ++k) x = _mm_max_epi16(x, m[k]);
  x = _mm_max_epi16(x, _mm_shuffle_epi32(x, 0x4E));
  x = _mm_max_epi16(x, _mm_shuffle_epi32(x, 0xB1));
  return _mm_max_epi16(x, _mm_shufflehi_epi16(_mm_shufflelo_epi16(x, 0xB1), 0xB1));
}

}  // namespace

void acs_sse2(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
              std::uint64_t* decisions) {
  // Plain arrays: std::array<__m128i> would drop the type's alignment attribute.
  __m128i sign_a[4];
  __m128i sign_b[4];
  __m128i m[8];
  for (std::size_t k = 0; k < 4; ++k) {
    sign_a[k] = load(kSignA.data() + 8 * k);
    sign_b[k] = load(kSignB.data() + 8 * k);
  }
  for (std::size_t k = 0; k < 8; ++k) {
    m[k] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(metrics + 8 * k));
  }
  for (std::size_t t = 0; t < n_steps; ++t) {
    const __m128i la = _mm_set1_epi16(sym[2 * t]);
    const __m128i lb = _mm_set1_epi16(sym[2 * t + 1]);
    __m128i next[8];
    std::uint64_t word = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      // Predecessors i = 8k ... 8k + 7 and i + 32; new states 16k ... 16k + 15.
      const __m128i bm =
          _mm_add_epi16(_mm_mullo_epi16(la, sign_a[k]), _mm_mullo_epi16(lb, sign_b[k]));
      const __m128i even_p0 = _mm_adds_epi16(m[k], bm);
      const __m128i even_p1 = _mm_subs_epi16(m[k + 4], bm);
      const __m128i odd_p0 = _mm_subs_epi16(m[k], bm);
      const __m128i odd_p1 = _mm_adds_epi16(m[k + 4], bm);
      const __m128i even = _mm_max_epi16(even_p0, even_p1);
      const __m128i odd = _mm_max_epi16(odd_p0, odd_p1);
      next[2 * k] = _mm_unpacklo_epi16(even, odd);
      next[2 * k + 1] = _mm_unpackhi_epi16(even, odd);
      const __m128i even_d = _mm_cmpgt_epi16(even_p1, even_p0);
      const __m128i odd_d = _mm_cmpgt_epi16(odd_p1, odd_p0);
      const __m128i in_order =
          _mm_packs_epi16(_mm_unpacklo_epi16(even_d, odd_d), _mm_unpackhi_epi16(even_d, odd_d));
      word |= static_cast<std::uint64_t>(static_cast<std::uint32_t>(_mm_movemask_epi8(in_order)))
              << (16 * k);
    }
    for (std::size_t k = 0; k < 8; ++k) m[k] = next[k];
    decisions[t] = word;
    if ((t + 1) % kRenormInterval == 0) {
      const __m128i top = max_all(m);
      for (__m128i& x : m) x = _mm_subs_epi16(x, top);
    }
  }
  for (std::size_t k = 0; k < 8; ++k) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(metrics + 8 * k), m[k]);
  }
}

}  // namespace rfsitl::phy::ofdm::viterbi

#endif  // __SSE2__
