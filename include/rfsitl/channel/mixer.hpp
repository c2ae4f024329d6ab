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

/// Several receivers over the same inputs: writes outs[r][t] = sum_i
/// coeffs[r * inputs.size() + i] * inputs[i][t] for every row r < outs.size()
/// and t in [0, n) (coeffs row-major, one row per output). The same sums as
/// mix() row by row, up to float rounding, but each input is read once per
/// group of rows, which is what keeps the FMA units busy once the inputs
/// outgrow L1. Preconditions: coeffs.size() == inputs.size() * outs.size();
/// every input and every out has n samples; no out overlaps an input or
/// another out. Pure: touches nothing but the outs.
void mix_rows(std::span<const cf32* const> inputs, std::span<const cf32> coeffs,
              std::span<cf32* const> outs, std::size_t n);

/// Adds sum_i (start[i] + t * step[i]) * inputs[i][t] to out[t] for t in
/// [0, out.size()): coefficients that ramp linearly across `out` (fading,
/// interpolated between grid points). Preconditions: the three spans of
/// coefficients' inputs have one size; every inputs[i] points to at least
/// out.size() samples; out overlaps no input. Pure: touches nothing but `out`.
void mix_ramped_add(std::span<const cf32* const> inputs, std::span<const cf32> start,
                    std::span<const cf32> step, std::span<cf32> out);

}  // namespace rfsitl::channel
