// The AVX-512BW add-compare-select kernel. The 64 int16 metrics live in two
// registers in state order (M0 = states 0..31, M1 = 32..63). vpermw gathers each
// new state's predecessors p0 = s >> 1 and p1 = (s >> 1) | 32 into lane s, so
// the results come out in state order and the compare masks are the decision
// bits themselves: no interleaving at all. Only this file's functions carry the
// avx512 target attribute; the caller checks the CPU first.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <array>

#include "viterbi_kernels.hpp"

#define RFSITL_AVX512 __attribute__((target("avx512f,avx512bw")))

namespace rfsitl::phy::ofdm::viterbi {
namespace {

/// vpermw indices gathering the predecessors of states base ... base + 31: lane
/// j reads lane ((base + j) >> 1) & 31 of M0 (its p0) and of M1 (its p1).
constexpr std::array<std::int16_t, 32> predecessor_lanes(unsigned base) {
  std::array<std::int16_t, 32> idx{};
  for (unsigned j = 0; j < 32; ++j) idx[j] = static_cast<std::int16_t>(((base + j) >> 1U) & 31U);
  return idx;
}
alignas(64) constexpr std::array<std::int16_t, 32> kLanesLow = predecessor_lanes(0);
alignas(64) constexpr std::array<std::int16_t, 32> kLanesHigh = predecessor_lanes(32);

/// Bit j set where the p0 branch into state base + j emits 1 on that output.
template <unsigned (*Output)(unsigned)>
constexpr __mmask32 ones_mask(unsigned base) {
  std::uint32_t m = 0;
  for (unsigned j = 0; j < 32; ++j) m |= static_cast<std::uint32_t>(Output(base + j)) << j;
  return m;
}

RFSITL_AVX512 inline __m512i load(const std::int16_t* p) {
  return _mm512_load_si512(static_cast<const void*>(p));
}

/// New metrics of 32 states in order, and their decision bits.
struct Half {
  __m512i metrics;
  __mmask32 from_p1;
};
RFSITL_AVX512 inline Half acs(__m512i p0, __m512i p1, __m512i bm) {
  const __m512i via_p0 = _mm512_adds_epi16(p0, bm);
  const __m512i via_p1 = _mm512_subs_epi16(p1, bm);
  return {_mm512_max_epi16(via_p0, via_p1), _mm512_cmpgt_epi16_mask(via_p1, via_p0)};
}

/// The maximum of 64 metrics, in every lane (vpermw by lane index xor k folds
/// without bringing in zeros).
RFSITL_AVX512 inline __m512i max_all(__m512i a, __m512i b) {
  __m512i m = _mm512_max_epi16(a, b);
  const __m512i lane = _mm512_set_epi16(31, 30, 29, 28, 27, 26, 25, 24, 23, 22, 21, 20, 19, 18, 17,
                                        16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  for (int k = 16; k >= 1; k /= 2) {
    const __m512i swapped = _mm512_xor_si512(lane, _mm512_set1_epi16(static_cast<short>(k)));
    m = _mm512_max_epi16(m, _mm512_permutexvar_epi16(swapped, m));
  }
  return m;
}

}  // namespace

RFSITL_AVX512 void acs_avx512(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
                              std::uint64_t* decisions) {
  constexpr __mmask32 kOnesA0 = ones_mask<branch_a>(0);
  constexpr __mmask32 kOnesB0 = ones_mask<branch_b>(0);
  constexpr __mmask32 kOnesA1 = ones_mask<branch_a>(32);
  constexpr __mmask32 kOnesB1 = ones_mask<branch_b>(32);
  const __m512i lanes_low = load(kLanesLow.data());
  const __m512i lanes_high = load(kLanesHigh.data());
  __m512i m0 = _mm512_loadu_si512(static_cast<const void*>(metrics));
  __m512i m1 = _mm512_loadu_si512(static_cast<const void*>(metrics + 32));
  for (std::size_t t = 0; t < n_steps; ++t) {
    const __m512i la = _mm512_set1_epi16(sym[2 * t]);
    const __m512i lb = _mm512_set1_epi16(sym[2 * t + 1]);
    const __m512i na = _mm512_sub_epi16(_mm512_setzero_si512(), la);
    const __m512i nb = _mm512_sub_epi16(_mm512_setzero_si512(), lb);
    // p0 -> s correlations: +l where the branch emits 0, -l where it emits 1.
    const __m512i bm0 = _mm512_add_epi16(_mm512_mask_blend_epi16(kOnesA0, la, na),
                                         _mm512_mask_blend_epi16(kOnesB0, lb, nb));
    const __m512i bm1 = _mm512_add_epi16(_mm512_mask_blend_epi16(kOnesA1, la, na),
                                         _mm512_mask_blend_epi16(kOnesB1, lb, nb));
    // States 0..31 have p0 in 0..15 (M0) and p1 in 32..47 (M1); states 32..63
    // have p0 in 16..31 and p1 in 48..63.
    const Half low =
        acs(_mm512_permutexvar_epi16(lanes_low, m0), _mm512_permutexvar_epi16(lanes_low, m1), bm0);
    const Half high = acs(_mm512_permutexvar_epi16(lanes_high, m0),
                          _mm512_permutexvar_epi16(lanes_high, m1), bm1);
    m0 = low.metrics;
    m1 = high.metrics;
    decisions[t] = (std::uint64_t{high.from_p1} << 32U) | low.from_p1;

    if ((t + 1) % kRenormInterval == 0) {
      const __m512i top = max_all(m0, m1);
      m0 = _mm512_subs_epi16(m0, top);
      m1 = _mm512_subs_epi16(m1, top);
    }
  }
  _mm512_storeu_si512(static_cast<void*>(metrics), m0);
  _mm512_storeu_si512(static_cast<void*>(metrics + 32), m1);
}

}  // namespace rfsitl::phy::ofdm::viterbi

#undef RFSITL_AVX512

#endif  // x86
