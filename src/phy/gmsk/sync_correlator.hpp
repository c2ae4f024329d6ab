#pragma once
/// Symbol timing and carrier phase from the sync word.
///
/// The input is the output of the filter matched to Laurent's pulse C0, one
/// value per sample. At the right timing the matched-filter values one symbol
/// apart are m_i ~ G j^i c_i (c_i the sync word's pseudo-symbols, G the complex
/// channel gain), so the correlator
///   C[n] = sum_i conj(j^i c_i) m[n - (S - 1 - i) k],  rho = |C|^2 / (S sum |m|^2)
/// peaks there (noise-free rho ~ 0.82 at k = 2, BT = 0.5: the part of the
/// matched-filter output that is missing is the neighbours' quadrature
/// interference) and G = C / S gives the carrier phase. On noise rho is
/// Beta(1, S - 1): P(rho > 0.4) ~ 1e-7 per sample.
///
/// The same correlation over the 32 preamble symbols before the sync word
/// (also known) gives a second gain G'; the phase from G' to G over their
/// 32-symbol distance is the carrier frequency offset.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class SyncCorrelator {
 public:
  explicit SyncCorrelator(unsigned samples_per_symbol);

  void reset();

  /// Feeds the matched-filter output of the next sample; returns rho (0..1).
  float push(cf32 mf);

  /// G = C / S for the window of the last push.
  cf32 gain() const { return gain_; }

  /// G' for the window of the last push: the gain over the 32 preamble symbols
  /// just before the sync word, were the sync word's last symbol there.
  cf32 preamble_gain() const;

 private:
  static constexpr std::size_t kTaps = 32;            // kSyncSymbols
  static constexpr std::size_t kHistory = 2 * kTaps;  // preamble tail and sync word

  /// Dot product of (rr + j ri) with the window x + j y, over kTaps.
  static cf32 correlate(const float* rr, const float* ri, const float* x, const float* y,
                        float* energy);

  unsigned k_;
  unsigned phase_ = 0;  // sample phase (t mod k) of the next input
  cf32 gain_{};
  const float* last_x_ = nullptr;  // window of the last push, oldest first
  const float* last_y_ = nullptr;
  // The reference conj(j^i c_i) = rr_i + j ri_i, as separate real arrays so
  // that the correlation is four dot products the compiler can vectorise.
  std::array<float, kTaps> rr_{};
  std::array<float, kTaps> ri_{};
  std::array<float, kTaps> pre_rr_{};  // the same for the preamble's last 32 symbols
  std::array<float, kTaps> pre_ri_{};
  // Per sample phase, the last kHistory matched-filter outputs (one per symbol),
  // written twice (at w and w + kHistory) so that the window is contiguous.
  std::vector<float> re_;  // k * 2 kHistory
  std::vector<float> im_;
  std::vector<std::size_t> pos_;  // per phase: next write index w in 0 .. kHistory - 1
};

}  // namespace rfsitl::phy::gmsk
