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
///
/// Values come in blocks: the correlations of a block's samples are
/// independent of each other, so the kernels compute several at once (across
/// samples, see receiver_kernels.hpp). Values before the last reset() count
/// as zeros.
#include <array>
#include <cstddef>
#include <vector>

#include "receiver_kernels.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class SyncCorrelator {
 public:
  /// The most values one push() takes.
  static constexpr std::size_t kMaxBlock = 64;

  SyncCorrelator(unsigned samples_per_symbol, const ReceiverKernels& kernels);

  void reset();

  /// Appends the matched-filter outputs of the next mf.size() samples and
  /// correlates at each. Precondition: mf.size() <= kMaxBlock.
  void push(std::span<const cf32> mf);

  /// rho (0..1) at the i-th sample of the last push. Precondition: i below its size.
  float rho(std::size_t i) const {
    const float e = energy_[i];
    const cf32 c{c_re_[i], c_im_[i]};
    return e > 0.0F ? std::norm(c) / (static_cast<float>(kTaps) * e) : 0.0F;
  }

  /// G = C / S at the i-th sample of the last push.
  cf32 gain(std::size_t i) const { return cf32{c_re_[i], c_im_[i]} / static_cast<float>(kTaps); }

  /// G' at the i-th sample of the last push: the gain over the 32 preamble
  /// symbols just before the sync word, were the sync word's last symbol there.
  cf32 preamble_gain(std::size_t i) const;

 private:
  static constexpr std::size_t kTaps = 32;  // kSyncSymbols

  const ReceiverKernels* kernels_;
  unsigned k_;
  std::size_t kept_;   // older values a window reaches back to: 2 kTaps - 1 symbols
  std::size_t first_;  // history index of the last push's first value
  std::size_t end_;    // history index one past the newest value
  // The reference conj(j^i c_i) = rr_i + j ri_i, as separate real arrays.
  std::array<float, kTaps> rr_{};
  std::array<float, kTaps> ri_{};
  std::array<float, kTaps> pre_rr_{};  // the same for the preamble's last 32 symbols
  std::array<float, kTaps> pre_ri_{};
  // The matched-filter outputs, oldest first, re and im apart; when full, the
  // last kept_ values move to the front.
  std::vector<float> re_;
  std::vector<float> im_;
  // The last push's correlations.
  std::array<float, kMaxBlock> c_re_{};
  std::array<float, kMaxBlock> c_im_{};
  std::array<float, kMaxBlock> energy_{};
};

}  // namespace rfsitl::phy::gmsk
