#include "rfsitl/channel/mixer.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <vector>

namespace rfsitl::channel {
namespace {

// The kernel works on the interleaved float view of std::complex<float>, which
// the standard explicitly allows ([complex.numbers]: a cf32 array may be
// accessed as an array of float with re at 2k and im at 2k+1). Writing the
// complex product by hand keeps GCC from emitting the C99 Annex G NaN/Inf
// fix-up call (__mulsc3) that std::complex operator* needs without -ffast-math.
//
// Register blocking: for each block of kBlock output samples the sum over all
// inputs is kept in local accumulators and the output is written once, so the
// memory traffic is one read of every input and one write of the output
// (instead of a read-modify-write of the output per input). Clones for AVX2+FMA
// and AVX-512 are selected at load time (GCC function multiversioning), so one
// binary uses the widest vectors the CPU has. Not under ASan or TSan: the
// clones' resolver runs while the dynamic loader relocates, before the
// sanitizer's runtime is set up, and its instrumented code crashes there.
constexpr std::size_t kBlock = 16;  // complex samples: 32 floats, 4 AVX2 registers

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define RFSITL_MIX_CLONES __attribute__((target_clones("default", "arch=haswell", "avx512f")))
#else
#define RFSITL_MIX_CLONES
#endif

RFSITL_MIX_CLONES
void mix_kernel(const float* const* __restrict xs, const float* __restrict cs, std::size_t n_in,
                float* __restrict y, std::size_t n) {
  std::size_t t = 0;
  for (; t + kBlock <= n; t += kBlock) {
    float acc[2 * kBlock] = {};
    for (std::size_t i = 0; i < n_in; ++i) {
      const float* __restrict x = xs[i] + 2 * t;
      const float cr = cs[2 * i];
      const float ci = cs[2 * i + 1];
      for (std::size_t j = 0; j < 2 * kBlock; j += 2) {
        acc[j] += cr * x[j] - ci * x[j + 1];
        acc[j + 1] += cr * x[j + 1] + ci * x[j];
      }
    }
    std::copy(acc, acc + 2 * kBlock, y + 2 * t);
  }
  for (; t < n; ++t) {  // tail: same expression per sample, one at a time
    float re = 0.0F;
    float im = 0.0F;
    for (std::size_t i = 0; i < n_in; ++i) {
      const float* x = xs[i] + 2 * t;
      re += cs[2 * i] * x[0] - cs[2 * i + 1] * x[1];
      im += cs[2 * i] * x[1] + cs[2 * i + 1] * x[0];
    }
    y[2 * t] = re;
    y[2 * t + 1] = im;
  }
}

// Inputs handed to the kernel per call (the emulator has at most 254 nodes, so
// one group always suffices there); more are summed group by group.
constexpr std::size_t kMaxGroup = 256;

}  // namespace

/// Additional precondition (implied by "touches nothing but out"): `out` does
/// not overlap any input; the kernel is compiled with that no-alias promise.
void mix(std::span<const cf32* const> inputs, std::span<const cf32> coeffs, std::span<cf32> out) {
  assert(inputs.size() == coeffs.size());
  const float* xs[kMaxGroup];
  float cs[2 * kMaxGroup];
  float* const y = reinterpret_cast<float*>(out.data());
  bool written = false;
  std::size_t k = 0;
  const auto flush = [&] {
    if (k == 0) return;
    if (!written) {
      mix_kernel(xs, cs, k, y, out.size());
      written = true;
    } else {
      thread_local std::vector<cf32> partial;
      partial.resize(out.size());
      mix_kernel(xs, cs, k, reinterpret_cast<float*>(partial.data()), out.size());
      for (std::size_t t = 0; t < out.size(); ++t) out[t] += partial[t];
    }
    k = 0;
  };
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const cf32 c = coeffs[i];
    // A zero coefficient (unknown position, or a model that underflowed) adds
    // nothing, so it costs nothing: it is left out of the kernel's inputs.
    if (c.real() == 0.0F && c.imag() == 0.0F) continue;
    xs[k] = reinterpret_cast<const float*>(inputs[i]);
    cs[2 * k] = c.real();
    cs[2 * k + 1] = c.imag();
    if (++k == kMaxGroup) flush();
  }
  flush();
  if (!written) std::fill(out.begin(), out.end(), cf32{0.0F, 0.0F});
}

void mix_ramped_add(std::span<const cf32* const> inputs, std::span<const cf32> start,
                    std::span<const cf32> step, std::span<cf32> out) {
  assert(inputs.size() == start.size() && inputs.size() == step.size());
  // Link by link: the ramps are short (one grid interval) and the links few
  // (those of active transmitters), so the plain loop is what GCC vectorizes.
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const float* __restrict x = reinterpret_cast<const float*>(inputs[i]);
    float* __restrict y = reinterpret_cast<float*>(out.data());
    const float c0r = start[i].real(), c0i = start[i].imag();
    const float dr = step[i].real(), di = step[i].imag();
    for (std::size_t t = 0; t < out.size(); ++t) {
      const auto tf = static_cast<float>(t);
      const float cr = c0r + tf * dr;
      const float ci = c0i + tf * di;
      y[2 * t] += cr * x[2 * t] - ci * x[2 * t + 1];
      y[2 * t + 1] += cr * x[2 * t + 1] + ci * x[2 * t];
    }
  }
}

}  // namespace rfsitl::channel
