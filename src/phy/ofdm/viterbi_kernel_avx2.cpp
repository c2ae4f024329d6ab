// The AVX2 add-compare-select kernel. The 64 int16 metrics live in four
// registers in state order (M0 = states 0..15, ..., M3 = 48..63). States 2i and
// 2i+1 share the predecessors i and i + 32, so the pairs (M0, M2) and (M1, M3)
// are lane-aligned butterflies; their even and odd results are interleaved back
// into state order with unpack + 128-bit permutes. Only this file's functions
// carry the avx2 target attribute; the caller checks the CPU first.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <array>

#include "viterbi_kernels.hpp"

namespace rfsitl::phy::ofdm::viterbi {
namespace {

__attribute__((target("avx2"))) inline __m256i load(const std::int16_t* p) {
  return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
}

/// One butterfly group: predecessors lo (states i) and hi (states i + 32), bm the
/// p0 -> 2i correlations. The p0 -> 2i+1 and p1 -> 2i branches score -bm, the
/// p1 -> 2i+1 branch +bm.
struct Butterfly {
  __m256i even, odd, even_from_p1, odd_from_p1;
};
__attribute__((target("avx2"))) inline Butterfly butterfly(__m256i lo, __m256i hi, __m256i bm) {
  const __m256i even_p0 = _mm256_adds_epi16(lo, bm);
  const __m256i even_p1 = _mm256_subs_epi16(hi, bm);
  const __m256i odd_p0 = _mm256_subs_epi16(lo, bm);
  const __m256i odd_p1 = _mm256_adds_epi16(hi, bm);
  return {_mm256_max_epi16(even_p0, even_p1), _mm256_max_epi16(odd_p0, odd_p1),
          _mm256_cmpgt_epi16(even_p1, even_p0), _mm256_cmpgt_epi16(odd_p1, odd_p0)};
}

/// The maximum of 64 metrics, in every lane. Shuffles, not byte shifts: a shift
/// would bring in zeros, larger than the all-negative metrics it should ignore.
__attribute__((target("avx2"))) inline __m256i max_all(__m256i a, __m256i b, __m256i c, __m256i d) {
  __m256i m = _mm256_max_epi16(_mm256_max_epi16(a, b), _mm256_max_epi16(c, d));
  m = _mm256_max_epi16(m, _mm256_permute2x128_si256(m, m, 0x01));
  m = _mm256_max_epi16(m, _mm256_shuffle_epi32(m, 0x4E));
  m = _mm256_max_epi16(m, _mm256_shuffle_epi32(m, 0xB1));
  // Each 32-bit element now holds (max of even lanes, max of odd lanes).
  return _mm256_max_epi16(m, _mm256_shufflehi_epi16(_mm256_shufflelo_epi16(m, 0xB1), 0xB1));
}

}  // namespace

__attribute__((target("avx2"))) void acs_avx2(const std::int16_t* sym, std::size_t n_steps,
                                              std::int16_t* metrics, std::uint64_t* decisions) {
  const __m256i sign_a0 = load(kSignA.data());
  const __m256i sign_a1 = load(kSignA.data() + 16);
  const __m256i sign_b0 = load(kSignB.data());
  const __m256i sign_b1 = load(kSignB.data() + 16);
  __m256i m0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(metrics));
  __m256i m1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(metrics + 16));
  __m256i m2 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(metrics + 32));
  __m256i m3 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(metrics + 48));
  for (std::size_t t = 0; t < n_steps; ++t) {
    const __m256i la = _mm256_set1_epi16(sym[2 * t]);
    const __m256i lb = _mm256_set1_epi16(sym[2 * t + 1]);
    const __m256i bm0 =
        _mm256_add_epi16(_mm256_sign_epi16(la, sign_a0), _mm256_sign_epi16(lb, sign_b0));
    const __m256i bm1 =
        _mm256_add_epi16(_mm256_sign_epi16(la, sign_a1), _mm256_sign_epi16(lb, sign_b1));
    const Butterfly g0 = butterfly(m0, m2, bm0);  // new states 0..31
    const Butterfly g1 = butterfly(m1, m3, bm1);  // new states 32..63

    // unpacklo/hi interleave within 128-bit halves: lo0 = states 0..7 | 16..23,
    // hi0 = 8..15 | 24..31; the permutes put the halves in order.
    const __m256i lo0 = _mm256_unpacklo_epi16(g0.even, g0.odd);
    const __m256i hi0 = _mm256_unpackhi_epi16(g0.even, g0.odd);
    const __m256i lo1 = _mm256_unpacklo_epi16(g1.even, g1.odd);
    const __m256i hi1 = _mm256_unpackhi_epi16(g1.even, g1.odd);
    m0 = _mm256_permute2x128_si256(lo0, hi0, 0x20);
    m1 = _mm256_permute2x128_si256(lo0, hi0, 0x31);
    m2 = _mm256_permute2x128_si256(lo1, hi1, 0x20);
    m3 = _mm256_permute2x128_si256(lo1, hi1, 0x31);

    // Decisions to one bit per state in state order. packs gives bytes
    // [even 0..7 of g0, of g1 | even 8..15 of g0, of g1] (in-lane); interleaving
    // the even and odd bytes then yields states 0..15 | 16..31 and 32..47 | 48..63.
    const __m256i even = _mm256_packs_epi16(g0.even_from_p1, g1.even_from_p1);
    const __m256i odd = _mm256_packs_epi16(g0.odd_from_p1, g1.odd_from_p1);
    const auto low =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_unpacklo_epi8(even, odd)));
    const auto high =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_unpackhi_epi8(even, odd)));
    decisions[t] = (std::uint64_t{high} << 32U) | low;

    if ((t + 1) % kRenormInterval == 0) {
      const __m256i top = max_all(m0, m1, m2, m3);
      m0 = _mm256_subs_epi16(m0, top);
      m1 = _mm256_subs_epi16(m1, top);
      m2 = _mm256_subs_epi16(m2, top);
      m3 = _mm256_subs_epi16(m3, top);
    }
  }
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(metrics), m0);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(metrics + 16), m1);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(metrics + 32), m2);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(metrics + 48), m3);
}

}  // namespace rfsitl::phy::ofdm::viterbi

#endif  // x86
