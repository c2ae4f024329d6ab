#include "ltf_search.hpp"

#include <cmath>
#include <complex>
#include <stdexcept>

#include "avx2_clones.hpp"

namespace rfsitl::phy::ofdm {
namespace {

/// C(m) += sum_k x[m + k] ref[k] for m in [0, lags), k in [0, 64), the lags in
/// the inner loop. Compiled for AVX2 and plain x86-64 (avx2_clones.hpp).
RFSITL_AVX2_CLONES void correlate(const float* xr, const float* xi, const float* ref_re,
                                  const float* ref_im, std::size_t lags, float* cr, float* ci) {
  for (std::size_t k = 0; k < 64; ++k) {
    const float a = ref_re[k];
    const float b = ref_im[k];
    for (std::size_t m = 0; m < lags; ++m) {
      cr[m] += xr[m + k] * a - xi[m + k] * b;
      ci[m] += xr[m + k] * b + xi[m + k] * a;
    }
  }
}

}  // namespace

LtfSearch::LtfSearch(std::span<const cf32, 64> ltf_time) {
  for (std::size_t k = 0; k < 64; ++k) {
    ref_re_[k] = ltf_time[k].real();
    ref_im_[k] = -ltf_time[k].imag();
  }
}

LtfTiming LtfSearch::find(std::span<const cf32> pkt, double coarse_cfo, std::size_t max_lag) {
  const std::size_t n = max_lag + 128;
  if (pkt.size() < n) throw std::invalid_argument("LtfSearch: packet shorter than max_lag + 128");
  re_.resize(n);
  im_.resize(n);
  // Derotate by a recursion re-anchored every 64 samples on an exact phasor, so
  // that the float rotator's rounding stays that of 64 steps.
  for (std::size_t start = 0; start < n; start += 64) {
    const double phase = -coarse_cfo * static_cast<double>(start);
    cf32 rot(static_cast<float>(std::cos(phase)), static_cast<float>(std::sin(phase)));
    const cf32 step(static_cast<float>(std::cos(coarse_cfo)),
                    static_cast<float>(-std::sin(coarse_cfo)));
    for (std::size_t i = start; i < std::min(n, start + 64); ++i) {
      const cf32 d = pkt[i] * rot;
      re_[i] = d.real();
      im_[i] = d.imag();
      rot *= step;
    }
  }
  // C(m) = sum_k d[m + k] conj(ltf[k]) for every lag m at once, k outermost.
  const std::size_t lags = max_lag + 65;
  c_re_.assign(lags, 0.0F);
  c_im_.assign(lags, 0.0F);
  correlate(re_.data(), im_.data(), ref_re_.data(), ref_im_.data(), lags, c_re_.data(),
            c_im_.data());
  const float* cr = c_re_.data();
  const float* ci = c_im_.data();
  float best = -1.0F;
  std::size_t t1 = 0;
  for (std::size_t m = 0; m <= max_lag; ++m) {
    const float metric = std::sqrt(cr[m] * cr[m] + ci[m] * ci[m]) +
                         std::sqrt(cr[m + 64] * cr[m + 64] + ci[m + 64] * ci[m + 64]);
    if (metric > best) {
      best = metric;
      t1 = m;
    }
  }
  // Residual offset from the repetitions T1 and T2 (after the coarse correction).
  std::complex<double> f;
  for (std::size_t k = 0; k < 64; ++k) {
    f += std::complex<double>(re_[t1 + k], im_[t1 + k]) *
         std::complex<double>(re_[t1 + 64 + k], -im_[t1 + 64 + k]);
  }
  return {t1, coarse_cfo - std::arg(f) / 64.0};
}

}  // namespace rfsitl::phy::ofdm
