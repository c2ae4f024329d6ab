#pragma once
/// The two per-sample soft symbol metrics of the GFSK receiver. Each step()
/// takes input sample y[n] and returns the decision value of a symbol whose
/// window ends at n: positive for the upper tone (+fd), negative for the
/// lower. Both are streaming and depend on nothing but the samples since
/// reset(), so any split of the input into blocks gives the same values.
///
/// Running sums over the last k values are updated by one addition and one
/// subtraction per sample and recomputed from their stored terms every
/// kResyncPeriod samples (counted from reset), so float rounding never builds up.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gfsk {

inline constexpr unsigned kResyncPeriod = 1024;

/// atan2(y, x) to within 1e-5 rad, without special cases (atan2(0, 0) = 0).
inline float fast_atan2(float y, float x) {
  const float ax = std::fabs(x);
  const float ay = std::fabs(y);
  // No comparisons that compile to branches: on noise each is a coin toss.
  const float lo = std::min(ax, ay);
  const float a = lo / (ax + ay - lo + 1e-30F);
  const float s = a * a;
  // Minimax polynomial for atan on [0, 1].
  float r =
      ((((0.0208351F * s - 0.0851330F) * s + 0.1801410F) * s - 0.3302995F) * s + 0.9998660F) * a;
  // The octant folds as arithmetic (compilers turn the plain selects into branches).
  const auto steep = static_cast<float>(ay > ax);
  r += steep * (std::numbers::pi_v<float> / 2.0F - 2.0F * r);
  const auto left = static_cast<float>(x < 0.0F);
  r += left * (std::numbers::pi_v<float> - 2.0F * r);
  return std::copysign(r, y);
}

/// Two-tone non-coherent energy detector:
///   C+-[n] = sum_{m < k} y[n - m] exp(-+j w (n - m)),  w = 2 pi fd = pi h / k,
/// metric |C+|^2 - |C-|^2 (independent of the carrier phase).
class EnergyMetric {
 public:
  EnergyMetric(unsigned samples_per_symbol, float modulation_index);
  void reset();

  float step(cf32 y) {
    if (++since_resync_ == kResyncPeriod) resync();
    const float cr = osc_.real();
    const float ci = osc_.imag();
    // y conj(osc) and y osc, written out (std::complex's operator* checks for inf).
    const cf32 up{y.real() * cr + y.imag() * ci, y.imag() * cr - y.real() * ci};
    const cf32 down{y.real() * cr - y.imag() * ci, y.imag() * cr + y.real() * ci};
    sum_up_ += up - up_[slot_];
    sum_down_ += down - down_[slot_];
    up_[slot_] = up;
    down_[slot_] = down;
    if (++slot_ == k_) slot_ = 0;
    osc_ = cf32{cr * rot_.real() - ci * rot_.imag(), cr * rot_.imag() + ci * rot_.real()};
    ++t_;
    return std::norm(sum_up_) - std::norm(sum_down_);
  }

 private:
  void resync();

  unsigned k_;
  double omega_;
  cf32 rot_;
  std::vector<cf32> up_;  // the last k terms of each sum, by n mod k
  std::vector<cf32> down_;
  cf32 sum_up_{};
  cf32 sum_down_{};
  cf32 osc_{1.0F, 0.0F};  // exp(j w t_)
  unsigned slot_ = 0;
  unsigned since_resync_ = 0;
  std::uint64_t t_ = 0;
};

/// FM discriminator with integrate-and-dump: u[n] = sum_{m < M} y[n - m] (a
/// boxcar channel filter), d[n] = arg(u[n] u*[n - 1]), metric sum_{m < k} d[n - m]
/// (the phase turned over the symbol, +-pi h for a long run of equal symbols).
class DiscriminatorMetric {
 public:
  /// M, the boxcar length: k / (h + 1), rounded, at least 1 (its first null
  /// at (h + 1) / k cycles per sample, Carson's bandwidth).
  static unsigned boxcar_length(unsigned samples_per_symbol, float modulation_index);

  DiscriminatorMetric(unsigned samples_per_symbol, float modulation_index);
  void reset();

  float step(cf32 y) {
    if (++since_resync_ == kResyncPeriod) resync();
    box_sum_ += y - box_[box_slot_];
    box_[box_slot_] = y;
    if (++box_slot_ == m_) box_slot_ = 0;
    const cf32 u = box_sum_;
    const float d = fast_atan2(u.imag() * prev_.real() - u.real() * prev_.imag(),
                               u.real() * prev_.real() + u.imag() * prev_.imag());
    prev_ = u;
    sum_ += d - d_[slot_];
    d_[slot_] = d;
    if (++slot_ == k_) slot_ = 0;
    return sum_;
  }

 private:
  void resync();

  unsigned k_;
  unsigned m_;
  std::vector<cf32> box_;  // the last M inputs
  cf32 box_sum_{};
  unsigned box_slot_ = 0;
  cf32 prev_{};
  std::vector<float> d_;  // the last k phase steps
  float sum_ = 0.0F;
  unsigned slot_ = 0;
  unsigned since_resync_ = 0;
};

}  // namespace rfsitl::phy::gfsk
