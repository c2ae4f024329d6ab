#include <algorithm>

#include "mix_kernels.hpp"

namespace rfsitl::channel::kernels {
namespace {
constexpr std::size_t kScalarBlock = 16;  // complex samples

}  // namespace

void mix_scalar(const float* const* __restrict xs, const float* __restrict cs, std::size_t n_in,
                float* __restrict y, std::size_t n) {
  std::size_t t = 0;
  for (; t + kScalarBlock <= n; t += kScalarBlock) {
    float acc[2 * kScalarBlock] = {};
    for (std::size_t i = 0; i < n_in; ++i) {
      const float* __restrict x = xs[i] + 2 * t;
      const float cr = cs[2 * i];
      const float ci = cs[2 * i + 1];
      for (std::size_t j = 0; j < 2 * kScalarBlock; j += 2) {
        acc[j] += cr * x[j] - ci * x[j + 1];
        acc[j + 1] += cr * x[j + 1] + ci * x[j];
      }
    }
    std::copy(acc, acc + 2 * kScalarBlock, y + 2 * t);
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

}  // namespace rfsitl::channel::kernels
