#pragma once
/// A frequency shift on the sample grid: x[t] times exp(j 2 pi f t / fs) at
/// absolute sample times t, so that a shifted signal is continuous from one
/// tick to the next whatever the tick size.
#include <cstdint>
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// Multiplies x[i] by exp(j 2 pi cycles_per_sample (first_sample + i)).
/// cycles_per_sample = f / fs; any value (a shift by a multiple of fs is the
/// identity on the grid). The phase is taken exactly (long double) every 256
/// samples and advanced by a double-precision rotation in between.
void shift_frequency(std::span<cf32> x, double cycles_per_sample, std::uint64_t first_sample);

}  // namespace rfsitl::channel
