#pragma once
/// The matched filter of one spreading code, working on chip-integrated samples
///   y[n] = x[n - S + 1] + ... + x[n]             (matched filter of a rectangular chip)
///   z[n] = sum_{i < L} c_i * y[n - (L - 1 - i) S]
/// so z[n] peaks (|z| = L * S * amplitude) when a code period ends at sample n.
/// Because chips are ±1, z is a sum and a difference of L samples: the filter
/// keeps the offsets of the +1 chips and of the -1 chips in two lists and adds
/// and subtracts, with no multiplications.
#include <cstddef>
#include <span>
#include <vector>

#include "codes.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::dsss {

class CodeCorrelator {
 public:
  /// Which implementation correlate_power() uses: kBest picks the widest vector
  /// unit the CPU has (AVX2 on x86-64 when present), kPortable the baseline one
  /// (SSE on x86-64); both compute the same sums. kPortable exists so that the
  /// tests cover the path a CPU without AVX2 takes.
  enum class Kernel { kBest, kPortable };

  /// Preconditions: chips not empty, samples_per_chip >= 1.
  CodeCorrelator(std::span<const Chip> chips, unsigned samples_per_chip,
                 Kernel kernel = Kernel::kBest);

  std::size_t code_length() const { return length_; }
  unsigned samples_per_chip() const { return samples_per_chip_; }
  /// Samples per code period, L * S.
  std::size_t period() const { return length_ * samples_per_chip_; }
  /// How far back one output reaches: z[n] reads y[n - lookback()] .. y[n].
  std::size_t lookback() const { return (length_ - 1) * samples_per_chip_; }

  /// z[n]. Precondition: `y` points at y[n] and y[n - lookback()] .. y[n] are readable.
  cf32 correlate(const cf32* y) const;

  /// power[j] = |z[n0 + j]|^2 for j < count. Precondition: `y` points at y[n0]
  /// and y[n0 - lookback()] .. y[n0 + count - 1] are readable.
  void correlate_power(const cf32* y, std::size_t count, float* power) const;

 private:
  std::size_t length_;
  unsigned samples_per_chip_;
  bool portable_;
  // Offsets back from y[n], in floats (two per complex sample), of the chips
  // that are +1 and of those that are -1.
  std::vector<std::size_t> plus_;
  std::vector<std::size_t> minus_;
};

}  // namespace rfsitl::phy::dsss
