#pragma once
// Internal to the channel module: the noise source's kernels, one file per
// instruction set (noise_source.cpp picks one from the CPU's features), all
// instantiating noise_math.hpp, so all give the same bits.
#include <cstdint>

namespace rfsitl::channel::noise_kernels {

/// Samples 32 g .. 32 g + 31 of the stream (key, stream) as 64 interleaved
/// floats (re, im, re, im, ...), `sigma` per dimension.
using GroupFn = void (*)(std::uint64_t group, const std::uint32_t key[2],
                         const std::uint32_t stream[2], float sigma, float* out);

void group_scalar(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                  float sigma, float* out);
/// Preconditions: the CPU has AVX2 and FMA.
void group_avx2(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                float sigma, float* out);
/// Precondition: the CPU has AVX-512F.
void group_avx512(std::uint64_t group, const std::uint32_t key[2], const std::uint32_t stream[2],
                  float sigma, float* out);

}  // namespace rfsitl::channel::noise_kernels
