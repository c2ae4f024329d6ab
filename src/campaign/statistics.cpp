#include "rfsitl/campaign/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rfsitl::campaign {
namespace {

/// The continued fraction of the regularized incomplete beta function
/// I_x(a, b), evaluated by the modified Lentz method; converges fast for
/// x < (a + 1) / (a + b + 2).
double beta_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEps = 1e-15;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  d = 1.0 / (std::fabs(d) < kTiny ? kTiny : d);
  double f = d;
  for (int m = 1; m <= 500; ++m) {
    for (const bool odd : {false, true}) {
      // d_{2m} = m (b - m) x / ((a + 2m - 1)(a + 2m)),
      // d_{2m+1} = -(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)).
      const double num = odd ? -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))
                             : m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
      d = 1.0 + num * d;
      d = 1.0 / (std::fabs(d) < kTiny ? kTiny : d);
      c = 1.0 + num / c;
      if (std::fabs(c) < kTiny) c = kTiny;
      const double step = c * d;
      f *= step;
      if (odd && std::fabs(step - 1.0) < kEps) return f;
    }
  }
  return f;
}

/// I_x(a, b), the regularized incomplete beta function.
double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  // The symmetry I_x(a, b) = 1 - I_{1-x}(b, a) keeps the fraction where it converges.
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

}  // namespace

double student_t_cdf(double t, double dof) {
  // P(|T| > |t|) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2).
  const double tail = 0.5 * incomplete_beta(dof / 2.0, 0.5, dof / (dof + t * t));
  return t >= 0.0 ? 1.0 - tail : tail;
}

double student_t_quantile(double p, double dof) {
  // Bisection on the monotone CDF: t at the right p to about 1e-12 relative.
  double lo = -1.0;
  double hi = 1.0;
  while (student_t_cdf(lo, dof) > p) lo *= 2.0;
  while (student_t_cdf(hi, dof) < p) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * std::max(1.0, std::fabs(hi)); ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

MeanInterval mean_ci95(const std::vector<double>& values) {
  MeanInterval r;
  r.n = values.size();
  const double n = static_cast<double>(r.n);
  r.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  if (r.n < 2) return r;
  double squares = 0.0;
  for (const double v : values) squares += (v - r.mean) * (v - r.mean);
  const double s = std::sqrt(squares / (n - 1.0));
  r.half_width = student_t_quantile(0.975, n - 1.0) * s / std::sqrt(n);
  return r;
}

}  // namespace rfsitl::campaign
