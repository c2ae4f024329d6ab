#pragma once
/// The fast GMSK receiver's inner loops (the search's matched filter and sync
/// correlation), in one version per instruction set, chosen once at run time
/// from the CPU's features as the channel's mixer does.
///
/// Every version computes each output with the same operations in the same
/// order as the scalar reference (the vectors run across outputs, never
/// across the terms of one sum; no fused multiply-add), so all versions give
/// the same bits and the receiver's decisions do not depend on the machine.
#include <cstddef>
#include <span>

namespace rfsitl::phy::gmsk {

struct ReceiverKernels {
  const char* name;  ///< "reference", "portable", "avx2", "avx512"

  /// out[j] = sum_{i < len} taps[i] in[j + 2 i] for j < n, each sum in tap
  /// order from 0: a real filter over interleaved complex samples (n counts
  /// floats, two per sample; re and im filter alike). Reads in[0 .. n + 2 len - 2).
  void (*matched_filter)(const float* in, const float* taps, std::size_t len, std::size_t n,
                         float* out);

  /// For m < n, the 32-tap correlation of the reference rr + j ri with the
  /// window x[m + i stride] + j y[m + i stride], i < 32 (oldest first):
  ///   c_re[m] + j c_im[m] = sum_i (rr_i + j ri_i)(x + j y),  energy[m] = sum_i |x + j y|^2,
  /// each summed in eight lanes (lane l takes i = l, l + 8, l + 16, l + 24 in
  /// order), then lanes 0 .. 7 added in order: SyncCorrelator's arithmetic.
  void (*correlate)(const float* x, const float* y, std::size_t stride, const float* rr,
                    const float* ri, std::size_t n, float* c_re, float* c_im, float* energy);
};

/// The scalar reference: one output at a time.
const ReceiverKernels& reference_kernels();

/// Every version this CPU runs, the reference first and the fastest last.
std::span<const ReceiverKernels* const> supported_kernels();

/// The fastest version this CPU runs (chosen once).
const ReceiverKernels& fastest_kernels();

}  // namespace rfsitl::phy::gmsk
