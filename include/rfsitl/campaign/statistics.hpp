#pragma once
/// Means over seeds and their 95 % confidence intervals (Student's t).
#include <cstddef>
#include <vector>

namespace rfsitl::campaign {

/// P(T <= t) for Student's t with `dof` > 0 degrees of freedom.
double student_t_cdf(double t, double dof);

/// The t with P(T <= t) = p, for p in (0, 1) and `dof` > 0.
double student_t_quantile(double p, double dof);

/// A sample's mean and the half-width of its two-sided 95 % confidence
/// interval, t(0.975, n-1) * s / sqrt(n) with s the sample standard deviation
/// (n - 1 in its denominator). One value: half_width 0 (no interval).
struct MeanInterval {
  double mean = 0.0;
  double half_width = 0.0;
  std::size_t n = 0;
};

/// Precondition: `values` is not empty.
MeanInterval mean_ci95(const std::vector<double>& values);

}  // namespace rfsitl::campaign
