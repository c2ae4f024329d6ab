#include "rfsitl/channel/mixer.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mix_kernels.hpp"

namespace rfsitl::channel {
namespace {

using kernels::kMaxGroup;

/// The widest kernels this CPU runs, chosen once.
struct Isa {
  bool avx512 = false;
  void (*mix)(const float* const*, const float*, std::size_t, float*,
              std::size_t) = kernels::mix_scalar;
};

Isa pick_isa() {
  Isa isa;
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) {
    isa.avx512 = true;
    isa.mix = kernels::mix_avx512;
  } else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    isa.mix = kernels::mix_avx2;
  }
  return isa;
}

const Isa isa = pick_isa();

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
      isa.mix(xs, cs, k, y, out.size());
      written = true;
    } else {
      thread_local std::vector<cf32> partial;
      partial.resize(out.size());
      isa.mix(xs, cs, k, reinterpret_cast<float*>(partial.data()), out.size());
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

void mix_rows(std::span<const cf32* const> inputs, std::span<const cf32> coeffs,
              std::span<cf32* const> outs, std::size_t n) {
  assert(coeffs.size() == inputs.size() * outs.size());
  const std::size_t n_in = inputs.size();
  const auto row = [&](std::size_t r) { return coeffs.subspan(r * n_in, n_in); };
  if (!isa.avx512 || n_in > kMaxGroup) {
    for (std::size_t r = 0; r < outs.size(); ++r) mix(inputs, row(r), {outs[r], n});
    return;
  }
  constexpr std::size_t kRows = 4;
  const float* xs[kMaxGroup];
  for (std::size_t i = 0; i < n_in; ++i) xs[i] = reinterpret_cast<const float*>(inputs[i]);
  const auto* cs = reinterpret_cast<const float*>(coeffs.data());
  std::uint32_t idx[kMaxGroup];
  for (std::size_t r0 = 0; r0 < outs.size(); r0 += kRows) {
    const std::size_t rows = std::min(kRows, outs.size() - r0);
    // Inputs whose coefficients are zero for every row of the group are left out.
    const float* group = cs + 2 * r0 * n_in;
    const std::size_t k = kernels::nonzero_columns_avx512(group, 2 * n_in, rows, n_in, idx);
    if (k == 0) {
      for (std::size_t r = 0; r < rows; ++r) std::fill_n(outs[r0 + r], n, cf32{0.0F, 0.0F});
      continue;
    }
    float* ys[kRows];
    for (std::size_t r = 0; r < rows; ++r) ys[r] = reinterpret_cast<float*>(outs[r0 + r]);
    kernels::mix_rows_avx512(xs, idx, k, group, 2 * n_in, rows, ys, n);
  }
}

void mix_ramped_add(std::span<const cf32* const> inputs, std::span<const cf32> start,
                    std::span<const cf32> step, std::span<cf32> out) {
  assert(inputs.size() == start.size() && inputs.size() == step.size());
  if (isa.avx512 && !out.empty()) {
    for (std::size_t i0 = 0; i0 < inputs.size(); i0 += kMaxGroup) {
      const std::size_t k = std::min(kMaxGroup, inputs.size() - i0);
      const float* xs[kMaxGroup];
      for (std::size_t i = 0; i < k; ++i) xs[i] = reinterpret_cast<const float*>(inputs[i0 + i]);
      kernels::mix_ramped_avx512(xs, reinterpret_cast<const float*>(start.data() + i0),
                                 reinterpret_cast<const float*>(step.data() + i0), k,
                                 reinterpret_cast<float*>(out.data()), out.size());
    }
    return;
  }
  // Link by link: the plain loop, for CPUs without AVX-512.
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
