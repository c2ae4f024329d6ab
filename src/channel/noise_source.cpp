#include "rfsitl/channel/noise_source.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "noise_kernels.hpp"

namespace rfsitl::channel {

NoiseSource::NoiseSource(std::uint64_t seed, std::uint64_t stream, float variance)
    : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
      stream_{static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)},
      variance_(variance),
      sigma_per_dim_(0.0) {
  if (!(variance >= 0.0f) || !std::isfinite(variance)) {
    throw std::invalid_argument("NoiseSource: variance must be finite and >= 0");
  }
  // E|eta|^2 = E[I^2] + E[Q^2], split evenly for circular noise.
  sigma_per_dim_ = std::sqrt(static_cast<double>(variance) / 2.0);
}

// Samples come in groups of 32: group g is Philox blocks 16 g .. 16 g + 15
// (counter = (block, stream)), block 16 g + j giving sample 32 g + j from its
// words 0-1 and sample 32 g + 16 + j from words 2-3, each by Box-Muller in
// single precision (noise_math.hpp). A kernel makes a whole group at a time;
// a buffer that starts or ends inside a group takes its part of it.
namespace {

struct Kernels {
  noise_kernels::GroupFn best = noise_kernels::group_scalar;
  bool avx2 = false;
  bool avx512 = false;
};

const Kernels& kernels() {
  static const Kernels k = [] {
    Kernels s;
    s.avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    s.avx512 = __builtin_cpu_supports("avx512f") && s.avx2;
    s.best = s.avx512 ? noise_kernels::group_avx512
             : s.avx2 ? noise_kernels::group_avx2
                      : noise_kernels::group_scalar;
    return s;
  }();
  return k;
}

noise_kernels::GroupFn kernel_of(NoiseKernel k) {
  if (!noise_kernel_supported(k)) {
    throw std::invalid_argument("NoiseSource: this CPU cannot run the requested kernel");
  }
  switch (k) {
    case NoiseKernel::kScalar:
      return noise_kernels::group_scalar;
    case NoiseKernel::kAvx2:
      return noise_kernels::group_avx2;
    case NoiseKernel::kAvx512:
      return noise_kernels::group_avx512;
    case NoiseKernel::kBest:
      break;
  }
  return kernels().best;
}

constexpr std::uint64_t kGroup = 32;

}  // namespace

bool noise_kernel_supported(NoiseKernel k) {
  switch (k) {
    case NoiseKernel::kAvx2:
      return kernels().avx2;
    case NoiseKernel::kAvx512:
      return kernels().avx512;
    case NoiseKernel::kBest:
    case NoiseKernel::kScalar:
      return true;
  }
  return false;
}

void NoiseSource::add_to(std::span<cf32> buf, std::uint64_t first_sample) const {
  add_to(buf, first_sample, NoiseKernel::kBest);
}

void NoiseSource::add_to(std::span<cf32> buf, std::uint64_t first_sample,
                         NoiseKernel kernel) const {
  if (variance_ == 0.0f || buf.empty()) return;
  const noise_kernels::GroupFn group_fn = kernel_of(kernel);
  const auto sigma = static_cast<float>(sigma_per_dim_);
  alignas(64) float group[2 * kGroup];
  std::size_t i = 0;
  while (i < buf.size()) {
    const std::uint64_t t = first_sample + i;
    group_fn(t / kGroup, key_.data(), stream_, sigma, group);
    const std::size_t from = t % kGroup;
    const std::size_t n = std::min<std::size_t>(kGroup - from, buf.size() - i);
    for (std::size_t k = 0; k < n; ++k) {
      buf[i + k] += cf32{group[2 * (from + k)], group[2 * (from + k) + 1]};
    }
    i += n;
  }
}

void NoiseSource::fill(std::span<cf32> buf, std::uint64_t first_sample) const {
  std::fill(buf.begin(), buf.end(), cf32{0.0f, 0.0f});
  add_to(buf, first_sample);
}

}  // namespace rfsitl::channel
