#pragma once
// Internal to the SIMD Viterbi decoder (viterbi_simd.cpp): the trellis of the
// 802.11 K = 7 (133, 171) code, the fixed-point ranges every kernel relies on,
// and the add-compare-select kernels, one per instruction set, each in a file of
// its own so that only that file's functions use the wider instructions.
#include <array>
#include <cstddef>
#include <cstdint>

namespace rfsitl::phy::ofdm::viterbi {

// Trellis. State s holds the last 6 input bits, the newest in bit 0, exactly as
// convolutional_encode()'s register after masking to 6 bits. Input b moves state
// p to s = ((p << 1) | b) & 63, so the two predecessors of s are
// p0 = s >> 1 and p1 = (s >> 1) | 32, and the 7-bit encoder register of that
// transition is s (from p0) or s | 64 (from p1). Both generators tap bit 6 (the
// oldest bit), so the p1 branch emits the complement of the p0 branch.
inline constexpr unsigned kStates = 64;
inline constexpr unsigned kMemory = 6;
inline constexpr unsigned kTapsA = 0b1101101;  // 133 octal, bit d = delay d
inline constexpr unsigned kTapsB = 0b1001111;  // 171 octal

constexpr unsigned parity7(unsigned v) {
  v &= 0x7FU;
  v ^= v >> 4U;
  v ^= v >> 2U;
  v ^= v >> 1U;
  return v & 1U;
}
/// Output A (resp. B) of the branch p0 -> s into state s.
constexpr unsigned branch_a(unsigned s) {
  return parity7(s & kTapsA);
}
constexpr unsigned branch_b(unsigned s) {
  return parity7(s & kTapsB);
}

/// +1 where the p0 branch into even state 2i emits 0 on an output, -1 where it
/// emits 1: the factor (AVX2 vpsignw, SSE2 pmullw) that turns the symbol's LLR
/// into that branch's score, for i < 32.
template <unsigned (*Output)(unsigned)>
constexpr std::array<std::int16_t, 32> even_state_signs() {
  std::array<std::int16_t, 32> signs{};
  for (unsigned i = 0; i < 32; ++i) signs[i] = Output(2 * i) != 0 ? -1 : 1;
  return signs;
}
alignas(32) inline constexpr std::array<std::int16_t, 32> kSignA = even_state_signs<branch_a>();
alignas(32) inline constexpr std::array<std::int16_t, 32> kSignB = even_state_signs<branch_b>();

// Fixed point. Path metrics are int16 correlations (to be maximized): a symbol
// with quantized LLR l adds +l to a branch that emits 0 and -l to one that emits
// 1, so one step moves a metric by at most 2 * kSymbolLimit = 254.
//
// Range: after step 6 every state is reachable from the best state of 6 steps
// earlier, so no metric trails the best by more than 6 * (254 + 254) = 3048.
// Renormalizing (subtracting the maximum) every kRenormInterval = 64 steps keeps
// metrics within [-3048 - kStartPenalty - 64 * 254, 64 * 254] = [-27496, 16256],
// inside int16. The kernels still use saturating adds, as a safety net only:
// within these bounds they never saturate, so every kernel is exact integer
// arithmetic and all kernels return identical decisions.
inline constexpr std::int16_t kSymbolLimit = 127;
inline constexpr std::size_t kRenormInterval = 64;
/// Initial metric of the states other than 0. A path out of state 0 reaches any
/// state within 6 steps losing at most 6 * 254 = 1524, a path out of another
/// state gains at most as much, so any penalty above 3048 means the survivors of
/// step 6 onwards all start in state 0: the start state is certain, not favoured.
inline constexpr std::int16_t kStartPenalty = 8192;

/// Add-compare-select over n_steps trellis steps.
/// - sym: 2 * n_steps quantized LLRs (A0 B0 A1 B1 ...), each in
///   [-kSymbolLimit, kSymbolLimit], positive meaning bit 0.
/// - metrics: the 64 path metrics in state order, read at the start and written
///   at the end.
/// - decisions: n_steps words; bit s of word t is set when the survivor into
///   state s after step t comes from p1 = (s >> 1) | 32 (strictly better than
///   p0; a tie keeps p0).
/// Metrics are renormalized after every kRenormInterval-th step of the call.
using AcsKernel = void (*)(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
                           std::uint64_t* decisions);

/// Plain C++ (any CPU); also the reference the vector kernels must match.
void acs_portable(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
                  std::uint64_t* decisions);
/// SSE2 (the x86-64 baseline): the 64 metrics in eight 8-lane registers.
void acs_sse2(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
              std::uint64_t* decisions);
/// AVX2: the 64 metrics in four 16-lane registers. Call only if the CPU has AVX2.
void acs_avx2(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
              std::uint64_t* decisions);
/// AVX-512BW: the 64 metrics in two 32-lane registers. Call only if the CPU has
/// AVX-512F and AVX-512BW.
void acs_avx512(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
                std::uint64_t* decisions);

}  // namespace rfsitl::phy::ofdm::viterbi
