#pragma once
/// The shadowing stage: log-normal shadowing (obstacles, terrain) that is
/// spatially correlated, deterministic and reciprocal.
///
/// Model. The shadowing of the link between nodes a < b (by index: the
/// unordered pair, so the stage is reciprocal) is S(p_a, p_b) in dB, a
/// zero-mean Gaussian random field over both ends' positions (their `local`
/// coordinates, metres) with separable exponential correlation, Gudmundson's
/// model at each end:
///   E[S(p_a, p_b) S(p_a', p_b')] = sigma^2 exp(-|p_a - p_a'| / d) exp(-|p_b - p_b'| / d),
/// d = decorrelation_m. The link's power gain is S dB: gain() = 10^(S / 20),
/// real (phase 0). A node's link to itself is not shadowed (S = 0).
///
/// Generation: a sum of M sinusoids (spectral synthesis),
///   S = sigma sqrt(2 / M) sum_i cos(k_i . p_a + q_i . p_b + phi_i),
/// phi_i uniform in [0, 2 pi), k_i and q_i independent 3-D wave vectors drawn
/// from the spectral density of exp(-r / d) in 3-D, (d^3 / pi^2) (1 + |k|^2 d^2)^-2:
/// the multivariate Cauchy (multivariate t, 1 degree of freedom),
/// k = z / (d |w|), z ~ N(0, I_3), w ~ N(0, 1). Why: given w, k is Gaussian with
/// variance 1 / (d w)^2 per axis, so E[cos(k . r) | w] = exp(-|r|^2 / (2 d^2 w^2)),
/// and averaging over w, (2 pi)^-1/2 int exp(-w^2 / 2 - a^2 / (2 w^2)) dw = exp(-a)
/// with a = |r| / d (the integral int_0^inf exp(-p x^2 - q / x^2) dx =
/// sqrt(pi / p) exp(-2 sqrt(p q)) / 2). Checked numerically as well (4e5 draws:
/// within 0.002 of exp(-|r| / d) at |r| = d/2, d, 2d, in three directions).
///
/// How the sum approaches the target as M grows: over the ensemble of links
/// (draws), the covariance is exactly the target for every M >= 1, because
/// E[cos(k . u + q . v)] = E[cos k . u] E[cos q . v] (k and q independent, each
/// symmetric). M sets two other things: (1) how Gaussian S is. Its excess
/// kurtosis is -3 / (2 M) (-0.047 at M = 32) and it is bounded by sigma sqrt(2 M);
/// by the central limit theorem it tends to the normal law. (2) How well one
/// link's own field, followed as its ends move, shows the exponential: its
/// spatial correlation at lag r is (1 / M) sum_i cos(k_i . r), a Monte Carlo
/// estimate of exp(-|r| / d) with standard deviation sqrt((1 - exp(-2 |r| / d)) / (2 M))
/// (at most 0.125 at M = 32). The Cauchy spectrum's heavy tail gives some
/// sinusoids short wavelengths: the field is rough at small lags, as
/// exp(-r / d) (not differentiable at 0) requires.
///
/// Determinism. Every draw is Philox4x32-10 (common/philox.hpp) under a key
/// derived from (stage seed, context.position), with counter = (a, b, sinusoid,
/// block): a link's field is fixed for the run and does not depend on the order,
/// or the thread, in which links are evaluated.
///
/// Cost: each gain() call evaluates M cosines, with 3 M Philox blocks, 4 M
/// logarithms and 8 M sines and cosines for the draws (nothing is cached, so the
/// stage holds no per-link memory). gain() is called O(N) times per node move.
#include <cstddef>
#include <cstdint>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

struct ShadowingSettings {
  double sigma_db = 4.0;          ///< the standard deviation of S, dB
  double decorrelation_m = 20.0;  ///< d: the correlation falls to 1/e over this distance
  std::uint32_t sinusoids = 32;   ///< M, the number of sinusoids summed
  std::uint64_t seed = 0;         ///< 0: the scenario's seed; otherwise this stage's own
};

const config::Fields<ShadowingSettings>& shadowing_fields();
ChannelStageComponent shadowing_component();

namespace shadowing {

/// S in dB for the link between `u` and `v` (in either order: the end with the
/// lower index is p_a), under the draws of (`seed`, `stage_position`). 0 when
/// u.index == v.index. `settings.seed` is not read: `seed` is the one in force
/// (settings.seed, or the scenario's when that is 0). Preconditions: settings
/// within their declared limits; node indices below 2^32. Pure, thread-safe.
double field_db(const ShadowingSettings& settings, std::uint64_t seed, std::size_t stage_position,
                const LinkEnd& u, const LinkEnd& v);

}  // namespace shadowing
}  // namespace rfsitl::channel
