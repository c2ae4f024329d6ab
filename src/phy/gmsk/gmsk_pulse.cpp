#include "gmsk_pulse.hpp"

#include <cmath>
#include <numbers>

namespace rfsitl::phy::gmsk {
namespace {

double gaussian_q(double x) {
  return 0.5 * std::erfc(x / std::numbers::sqrt2);
}

double std_normal_pdf(double x) {
  return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
}

}  // namespace

double gaussian_phase_pulse(double t, double bt) {
  // g(u) = (1/2) [Q(a (u - 1/2)) - Q(a (u + 1/2))] and an antiderivative of Q(a x)
  // is F(x) = x Q(a x) - pdf(a x) / a. Integrating g from -inf, the two F terms'
  // limits at -inf differ by exactly 1 (Q -> 1 there), which gives the closed form.
  const double a = 2.0 * std::numbers::pi * bt / std::sqrt(std::numbers::ln2);
  const auto f = [a](double x) { return x * gaussian_q(a * x) - std_normal_pdf(a * x) / a; };
  return 0.5 * (f(t - 0.5) - f(t + 0.5) + 1.0);
}

unsigned gaussian_span_symbols(double bt) {
  if (bt <= 0.0) return 1;
  const double sigma = std::sqrt(std::numbers::ln2) / (2.0 * std::numbers::pi * bt);
  return static_cast<unsigned>(std::ceil(1.0 + 6.0 * sigma));
}

GmskPulse make_gmsk_pulse(unsigned k, double bt, unsigned span) {
  GmskPulse p;
  p.samples_per_symbol = k;
  p.span_symbols = span;
  const double half = 0.5 * span;
  const double q0 = gaussian_phase_pulse(-half, bt);
  const double scale = 0.5 / (gaussian_phase_pulse(half, bt) - q0);
  // Truncated, causal and renormalised phase pulse: qt(t) for t in [0, L].
  const auto qt = [&](double t) {
    if (t <= 0.0) return 0.0;
    if (t >= span) return 0.5;
    return scale * (gaussian_phase_pulse(t - half, bt) - q0);
  };
  const unsigned lk = span * k;
  p.phase.resize(lk + 1);
  for (unsigned j = 0; j <= lk; ++j) p.phase[j] = std::numbers::pi * qt(static_cast<double>(j) / k);

  // Laurent: S(t) = sin(psi(t)) / sin(pi h), psi = 2 pi h qt(t) on [0, LT] and
  // pi h - 2 pi h qt(t - LT) on [LT, 2LT] (h = 1/2, sin(pi h) = 1), and
  // C0(t) = prod_{i < L} S(t + iT), supported on [0, (L + 1) T].
  const auto s_pulse = [&](double t) {
    if (t <= 0.0 || t >= 2.0 * span) return 0.0;
    const double psi = t <= span ? std::numbers::pi * qt(t)
                                 : 0.5 * std::numbers::pi - std::numbers::pi * qt(t - span);
    return std::sin(psi);
  };
  const unsigned c0_len = (span + 1) * k - 1;
  p.c0.resize(c0_len);
  double energy = 0.0;
  std::vector<double> c0(c0_len);
  for (unsigned j = 0; j < c0_len; ++j) {
    const double t = static_cast<double>(j + 1) / k;
    double v = 1.0;
    for (unsigned i = 0; i < span; ++i) v *= s_pulse(t + i);
    c0[j] = v;
    energy += v * v;
  }
  const double norm = 1.0 / std::sqrt(energy);
  for (unsigned j = 0; j < c0_len; ++j) p.c0[j] = static_cast<float>(c0[j] * norm);
  return p;
}

}  // namespace rfsitl::phy::gmsk
