#pragma once
/// The interference channel's mixing kernel: y = sum_n c_n x_n.
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// Writes out[t] = sum_i coeffs[i] * inputs[i][t] for t in [0, out.size()).
/// Preconditions: coeffs.size() == inputs.size(); every inputs[i] points to at
/// least out.size() samples. With no inputs, out is zero-filled. Pure: touches
/// nothing but `out`.
void mix(std::span<const cf32* const> inputs, std::span<const cf32> coeffs, std::span<cf32> out);

/// Adds sum_i (start[i] + t * step[i]) * inputs[i][t] to out[t] for t in
/// [0, out.size()): coefficients that ramp linearly across `out` (fading,
/// interpolated between grid points). Preconditions: the three spans of
/// coefficients' inputs have one size; every inputs[i] points to at least
/// out.size() samples; out overlaps no input. Pure: touches nothing but `out`.
void mix_ramped_add(std::span<const cf32* const> inputs, std::span<const cf32> start,
                    std::span<const cf32> step, std::span<cf32> out);

}  // namespace rfsitl::channel
