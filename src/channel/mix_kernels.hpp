#pragma once
// The mixer's kernels, one file per instruction set (mixer.cpp picks one from
// the CPU's features; x86-64, as the whole build). Internal to the channel
// module.
//
// The kernels work on the interleaved float view of std::complex<float>, which
// the standard explicitly allows ([complex.numbers]: a cf32 array may be
// accessed as an array of float with re at 2k and im at 2k+1). Writing the
// complex product by hand keeps GCC from emitting the C99 Annex G NaN/Inf
// fix-up call (__mulsc3) that std::complex operator* needs without -ffast-math.
//
// Register blocking: for each block of output samples the sum over all inputs
// is kept in registers and the output is written once, so the memory traffic is
// one read of every input and one write of the output (instead of a
// read-modify-write of the output per input).
//
// The SIMD kernels keep re and im interleaved and need no shuffle per input:
// with x = (xr, xi) pairs, they sum a += c_re * x and b += c_im * x over the
// inputs (two independent FMAs per vector, the FMA peak's own instruction mix),
// and only at the end of a block form y = a + (-b_im, b_re): one shuffle per
// output vector, since exchanging re and im commutes with the sum. Each input's
// block is several cache lines long so that the hardware prefetcher follows it.
// mixer.cpp chooses the kernel once from the CPU's features (a plain function
// pointer, not an ifunc, so it works under the sanitizers too).
#include <cstddef>
#include <cstdint>

namespace rfsitl::channel::kernels {

/// Inputs handed to a kernel per call (the emulator has at most 254 nodes, so
/// one group always suffices there); mix() sums more group by group.
constexpr std::size_t kMaxGroup = 256;

/// y[t] = sum_i (cs[2i] + j cs[2i+1]) xs[i][t] for t < n, interleaved floats.
/// Preconditions: n_in <= kMaxGroup; y overlaps no input.
void mix_scalar(const float* const* xs, const float* cs, std::size_t n_in, float* y, std::size_t n);
void mix_avx2(const float* const* xs, const float* cs, std::size_t n_in, float* y, std::size_t n);
void mix_avx512(const float* const* xs, const float* cs, std::size_t n_in, float* y, std::size_t n);

/// ys[r][t] = sum_m (c_r[2 i] + j c_r[2 i + 1]) xs[i][t] with i = idx[m], m <
/// n_idx, for r < rows <= 4, where row r's coefficients c_r = cs + r stride
/// (interleaved floats, indexed like xs): bit for bit mix_avx512 of each row
/// over the inputs idx names, in that order. Preconditions: as mix_avx512; no y
/// overlaps another.
void mix_rows_avx512(const float* const* xs, const std::uint32_t* idx, std::size_t n_idx,
                     const float* cs, std::size_t stride, std::size_t rows, float* const* ys,
                     std::size_t n);

/// Writes to idx, in order, each i < n_in whose coefficient (cs[r stride + 2i],
/// cs[r stride + 2i + 1]) is not zero in at least one row r < rows, and returns
/// how many it wrote (an input all rows weigh by zero adds nothing). idx holds
/// n_in entries.
std::size_t nonzero_columns_avx512(const float* cs, std::size_t stride, std::size_t rows,
                                   std::size_t n_in, std::uint32_t* idx);

/// y[t] += sum_i (c0_i + t d_i) xs[i][t] for t < n, coefficients interleaved
/// like cs. Preconditions: as mix_avx512.
void mix_ramped_avx512(const float* const* xs, const float* c0, const float* d, std::size_t n_in,
                       float* y, std::size_t n);

}  // namespace rfsitl::channel::kernels
