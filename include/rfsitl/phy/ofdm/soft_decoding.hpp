#pragma once
/// The receive side of the bit pipeline: soft demapping, deinterleaving,
/// depuncturing and Viterbi decoding. Soft values are log-likelihood ratios
/// scaled so that llr > 0 means bit 0 is more likely... see each function; all
/// share one convention: llr = log(P(b=0)/P(b=1)).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/phy/ofdm/rates.hpp"

namespace rfsitl::phy::ofdm {

/// Soft-demaps one equalized point of the 17.3.5.8 constellation into n_bpsc
/// LLRs (max-log approximation). `noise_var` is the post-equalization noise
/// variance of this subcarrier (> 0). Precondition: out.size() == n_bpsc.
void demap_soft(cf32 point, unsigned n_bpsc, float noise_var, std::span<float> out);

/// Inverse of interleave() for one symbol of soft values.
std::vector<float> deinterleave(std::span<const float> in, unsigned n_bpsc);

/// Re-inserts the punctured positions as erasures (llr 0), giving a rate-1/2
/// stream of 2 * n_data_bits values. Precondition: in.size() matches the
/// punctured length of n_data_bits at `rate`.
std::vector<float> depuncture(std::span<const float> in, CodeRate rate, std::size_t n_data_bits);

/// Soft-decision Viterbi decoder for the K = 7 (133, 171) code.
class ViterbiDecoder {
 public:
  virtual ~ViterbiDecoder() = default;
  /// Decodes n_bits data bits from 2 * n_bits rate-1/2 LLRs (A0 B0 A1 B1 ...).
  /// The trellis starts in state 0; if `terminated`, the last 6 data bits are the
  /// zero tail and the path is forced to end in state 0.
  virtual std::vector<std::uint8_t> decode(std::span<const float> llr, std::size_t n_bits,
                                           bool terminated) = 0;
};

/// A decoder built on libfec's viterbi27 (Debian libfec-dev).
std::unique_ptr<ViterbiDecoder> make_viterbi_decoder();

}  // namespace rfsitl::phy::ofdm
