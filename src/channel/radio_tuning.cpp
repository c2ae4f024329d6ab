#include "rfsitl/channel/radio_tuning.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rfsitl::channel {
namespace {

/// The integral of the density from the centre to offset x >= 0. Between two
/// points the density is 10^((d0 + s (u - x0)) / 10) with s the slope in dB per
/// unit: its integral is closed-form.
double power_from_centre(const std::vector<MaskPoint>& p, double x) {
  constexpr double kLn10Over10 = 0.23025850929940458;  // ln(10) / 10
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < p.size() && x > p[i].offset; ++i) {
    const double x0 = p[i].offset;
    const double width = p[i + 1].offset - x0;
    if (width <= 0.0) continue;
    const double x1 = std::min(x, p[i + 1].offset);
    const double slope = (p[i + 1].dbr - p[i].dbr) / width;
    const double d0 = std::pow(10.0, p[i].dbr / 10.0);
    if (slope == 0.0) {
      sum += d0 * (x1 - x0);
    } else {
      const double k = kLn10Over10 * slope;
      sum += d0 * std::expm1(k * (x1 - x0)) / k;
    }
  }
  return sum;
}

/// The integral from the centre to a signed offset (negative: the lower side).
double signed_power(const std::vector<MaskPoint>& p, double x) {
  return x >= 0.0 ? power_from_centre(p, x) : -power_from_centre(p, -x);
}

}  // namespace

double mask_power_fraction(const std::vector<MaskPoint>& p, double lo, double hi) {
  const double total = 2.0 * power_from_centre(p, p.back().offset);
  if (!(total > 0.0) || !(hi > lo)) return 0.0;
  return std::clamp((signed_power(p, hi) - signed_power(p, lo)) / total, 0.0, 1.0);
}

LinkBand link_band(const RadioTuning& tx, const RadioTuning& rx, double sample_rate_hz) {
  LinkBand b;
  b.offset_hz = tx.tx_hz - rx.rx_hz;
  // A relative tolerance: channel centres computed from a plan's first_hz and
  // spacing_hz are a few ulp off the ones the user had in mind.
  const double slack = 1e-9 * std::max(tx.bandwidth_hz, rx.bandwidth_hz);
  if (std::abs(b.offset_hz) + tx.bandwidth_hz / 2 <= rx.bandwidth_hz / 2 + slack) return b;
  // m's band in offsets from n's centre, in the unit of n's mask: the sample
  // rate, or n's channel bandwidth for the flat mask an empty one stands for.
  static const std::vector<MaskPoint> kFlat{{0.0, 0.0}, {0.5, 0.0}};
  const bool flat = tx.mask.points.empty();
  const double unit = flat ? tx.bandwidth_hz : sample_rate_hz;
  const double lo = (-b.offset_hz - rx.bandwidth_hz / 2) / unit;
  const double hi = (-b.offset_hz + rx.bandwidth_hz / 2) / unit;
  const double kappa = mask_power_fraction(flat ? kFlat : tx.mask.points, lo, hi);
  b.relation = kappa >= kLeakageFloor ? BandRelation::kLeaking : BandRelation::kOutOfBand;
  b.kappa = b.relation == BandRelation::kLeaking ? static_cast<float>(kappa) : 0.0F;
  return b;
}

}  // namespace rfsitl::channel
