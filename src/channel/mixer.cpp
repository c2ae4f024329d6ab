#include "rfsitl/channel/mixer.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>

namespace rfsitl::channel {
namespace {

// The kernels work on the interleaved float view of std::complex<float>, which
// the standard explicitly allows ([complex.numbers]: a cf32 array may be
// accessed as an array of float with re at 2k and im at 2k+1). Writing the
// complex product by hand keeps GCC from emitting the C99 Annex G NaN/Inf
// fix-up call (__mulsc3) that std::complex operator* needs without
// -ffast-math, and lets the vectorizer see plain float arithmetic.
//
// Written as y = cr*x + (-ci, ci)*swap(x): with the sign folded into a
// per-lane constant the loop becomes two multiplies, one shuffle and two adds
// per vector, with no blend.
//
// Samples are processed in fixed blocks of kBlock floats so that GCC's
// "very cheap" vectorizer cost model used at -O2 (GCC >= 12) can vectorize
// without needing a runtime epilogue decision; the tail uses the same
// per-sample expression, so a sample's value never depends on where it sits.
constexpr std::size_t kBlock = 16;  // 8 complex samples: one AVX or two SSE vectors

/// y[k..k+1] = c * x[k..k+1] (kAccumulate false: the first contributor, so no
/// read of y and no zero-fill pass) or y[k..k+1] += c * x[k..k+1].
template <bool kAccumulate>
inline void scale(float* __restrict y, const float* __restrict x, float cr, float ci,
                  std::size_t n_floats) {
  const auto put = [y](std::size_t k, float v) {
    if constexpr (kAccumulate) {
      y[k] += v;
    } else {
      y[k] = v;
    }
  };
  std::size_t k = 0;
  const std::size_t n_blocked = n_floats - n_floats % kBlock;
  for (; k < n_blocked; k += kBlock) {
    for (std::size_t j = 0; j < kBlock; j += 2) {
      put(k + j, cr * x[k + j] - ci * x[k + j + 1]);
      put(k + j + 1, cr * x[k + j + 1] + ci * x[k + j]);
    }
  }
  for (; k < n_floats; k += 2) {
    put(k, cr * x[k] - ci * x[k + 1]);
    put(k + 1, cr * x[k + 1] + ci * x[k]);
  }
}

}  // namespace

/// Additional precondition (implied by "touches nothing but out"): `out` does
/// not overlap any input; the kernels are compiled with that no-alias promise.
void mix(std::span<const cf32* const> inputs, std::span<const cf32> coeffs, std::span<cf32> out) {
  assert(inputs.size() == coeffs.size());
  const std::size_t n_floats = 2 * out.size();
  float* const y = reinterpret_cast<float*>(out.data());
  bool written = false;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const cf32 c = coeffs[i];
    // A zero coefficient (unknown position, or a model that underflowed) adds
    // nothing, so it costs nothing: no pass over its samples.
    if (c.real() == 0.0f && c.imag() == 0.0f) {
      continue;
    }
    const float* const x = reinterpret_cast<const float*>(inputs[i]);
    if (!written) {
      scale<false>(y, x, c.real(), c.imag(), n_floats);
      written = true;
    } else {
      scale<true>(y, x, c.real(), c.imag(), n_floats);
    }
  }
  if (!written) {
    std::fill(out.begin(), out.end(), cf32{0.0f, 0.0f});
  }
}

}  // namespace rfsitl::channel
