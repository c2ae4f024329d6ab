#pragma once
/// The receive side of the bit pipeline: soft demapping, deinterleaving,
/// depuncturing and Viterbi decoding, the inverses of bit_pipeline.hpp. All soft
/// values share one convention: llr = log(P(b=0)/P(b=1)), so llr > 0 means bit 0
/// is more likely, the magnitude is the confidence and llr = 0 is an erasure (no
/// information). Size violations throw std::invalid_argument.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "rates.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

/// Soft-demaps one equalized point of the 17.3.5.8 constellation into n_bpsc
/// LLRs (max-log approximation), in bit order b0 b1 ... as map_point() takes them.
/// `noise_var` is the post-equalization complex noise variance E|n|^2 of this
/// subcarrier (> 0; infinity gives erasures). Precondition: out.size() == n_bpsc.
void demap_soft(cf32 point, unsigned n_bpsc, float noise_var, std::span<float> out);

/// demap_soft() of a whole symbol: point d with noise_var[d] into
/// out[d * n_bpsc, (d + 1) * n_bpsc), the same values as one call per point.
/// Preconditions: noise_var.size() == points.size(), out.size() ==
/// points.size() * n_bpsc, n_bpsc one of 1, 2, 4, 6, every noise_var > 0.
void demap_symbol(std::span<const cf32> points, std::span<const float> noise_var, unsigned n_bpsc,
                  std::span<float> out);

/// Inverse of interleave() for one symbol of soft values (n_cbps = in.size()).
std::vector<float> deinterleave(std::span<const float> in, unsigned n_bpsc);

/// deinterleave() into `out` without allocating (for the standard symbol sizes).
/// Precondition: out.size() == in.size().
void deinterleave_into(std::span<const float> in, unsigned n_bpsc, std::span<float> out);

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
  /// zero tail and the path is forced to end in state 0 (those 6 bits come back
  /// as 0; precondition n_bits >= 6), otherwise it ends in the best state. Only
  /// the LLRs' relative sizes matter: a common positive factor changes nothing.
  /// Returns n_bits bits. Not thread-safe; use one decoder per thread.
  virtual std::vector<std::uint8_t> decode(std::span<const float> llr, std::size_t n_bits,
                                           bool terminated) = 0;
};

/// The default decoder: make_simd_viterbi_decoder(ViterbiKernel::kBest).
std::unique_ptr<ViterbiDecoder> make_viterbi_decoder();

/// Instruction sets of the built-in decoder's add-compare-select loop. All kernels
/// compute the same exact integer recursion and return identical bits.
enum class ViterbiKernel {
  kBest,      ///< the fastest one this CPU supports (AVX-512BW, AVX2, SSE2, portable)
  kPortable,  ///< plain C++, any CPU (slow: the reference for the others)
  kSse2,      ///< any x86-64
  kAvx2,
  kAvx512,  ///< AVX-512F + AVX-512BW
};

/// True if this CPU (and OS) can run `kernel`; kBest and kPortable always can.
bool viterbi_kernel_supported(ViterbiKernel kernel);

/// The built-in decoder (viterbi_simd.cpp): LLRs quantized per block to 8 bits
/// (the mean finite nonzero |LLR| maps to 40, clipped at 127; infinities to
/// +-127, NaN to an erasure), exact int16 path metrics, full-block traceback
/// (it keeps 12 bytes per data bit of the longest block it has decoded).
/// Throws std::invalid_argument if `kernel` is not supported here.
std::unique_ptr<ViterbiDecoder> make_simd_viterbi_decoder(
    ViterbiKernel kernel = ViterbiKernel::kBest);

/// A decoder built on libfec's viterbi27 (Debian libfec-dev, portable C; 12 to 14
/// times slower than the AVX2 / AVX-512 kernels): the independent reference the
/// built-in decoder is tested against.
std::unique_ptr<ViterbiDecoder> make_libfec_viterbi_decoder();

}  // namespace rfsitl::phy::ofdm
