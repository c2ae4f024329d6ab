// The portable add-compare-select kernel: one state at a time, with the same
// saturating int16 arithmetic, tie rule and renormalization schedule as the
// vector kernels, so that it serves as their reference (viterbi_kernels.hpp).
#include <algorithm>
#include <array>
#include <limits>

#include "viterbi_kernels.hpp"

namespace rfsitl::phy::ofdm::viterbi {
namespace {

/// What _mm*_adds_epi16 / _mm*_subs_epi16 do with an exact sum.
std::int16_t saturate(int v) {
  return static_cast<std::int16_t>(std::clamp<int>(v, std::numeric_limits<std::int16_t>::min(),
                                                   std::numeric_limits<std::int16_t>::max()));
}

}  // namespace

void acs_portable(const std::int16_t* sym, std::size_t n_steps, std::int16_t* metrics,
                  std::uint64_t* decisions) {
  std::array<std::int16_t, kStates> old{};
  std::array<std::int16_t, kStates> next{};
  std::copy_n(metrics, kStates, old.begin());
  for (std::size_t t = 0; t < n_steps; ++t) {
    const int la = sym[2 * t];
    const int lb = sym[2 * t + 1];
    std::uint64_t word = 0;
    for (unsigned s = 0; s < kStates; ++s) {
      // Correlation of the p0 -> s branch; the p1 -> s branch emits the
      // complement and scores its negative.
      const int bm = (branch_a(s) != 0 ? -la : la) + (branch_b(s) != 0 ? -lb : lb);
      const std::int16_t from_p0 = saturate(old[s >> 1U] + bm);
      const std::int16_t from_p1 = saturate(old[(s >> 1U) | 32U] - bm);
      next[s] = std::max(from_p0, from_p1);
      if (from_p1 > from_p0) word |= std::uint64_t{1} << s;
    }
    decisions[t] = word;
    old = next;
    if ((t + 1) % kRenormInterval == 0) {
      const int top = *std::max_element(old.begin(), old.end());
      for (std::int16_t& m : old) m = saturate(m - top);
    }
  }
  std::copy(old.begin(), old.end(), metrics);
}

}  // namespace rfsitl::phy::ofdm::viterbi
