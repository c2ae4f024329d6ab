#pragma once
/// The fading stage: small-scale (fast) fading, Rayleigh or Rician, whose
/// Doppler follows the ends' real motion.
///
/// Model. A link's gain is a random field over both ends' positions (their
/// `local` coordinates, metres), the scatter of M plane waves:
///   g(p_tx, p_rx) = sqrt(1 / M) sum_i exp(j (phi_i + k_i . p_tx + q_i . p_rx)),
/// k_i = (2 pi / lambda) (cos a_i, sin a_i, 0), q_i = (2 pi / lambda) (cos b_i, sin b_i, 0):
/// departure and arrival azimuths a_i, b_i and phases phi_i independent and
/// uniform (isotropic scattering in the horizontal plane, Clarke's model at
/// each end). A node moving at v turns sinusoid i's phase at (k_i . v) / (2 pi)
/// Hz, a Doppler shift of (v / lambda) cos(a_i - heading): so the gain's
/// autocorrelation over the ensemble of links is J0(2 pi f_tx tau) with one end
/// moving (f = v / lambda) and J0(2 pi f_tx tau) J0(2 pi f_rx tau) with both
/// (Akki and Haber), for every M (the draws are independent and symmetric).
/// M sets how Gaussian g is (by the central limit theorem; 32 by default).
/// Rician: h = sqrt(K / (K + 1)) exp(j (phi_0 - 2 pi d / lambda)) + sqrt(1 / (K + 1)) g,
/// d = |p_rx - p_tx|: the line-of-sight wave, whose phase turns with the
/// distance, so two nodes moving apart at v shift it by -v / lambda = -v fc / c.
/// Rayleigh: h = g. E|h|^2 = 1: the stage adds no mean gain.
///
/// Dispersive links (delay, multipath before this stage): every path p gets a
/// field of its own (its own M draws), so the taps fade independently, as in a
/// tapped-delay-line model; a Rician stage's line-of-sight wave is on path 0,
/// the first arrival, and the later paths are Rayleigh.
///
/// Time. The engine evaluates the gain on a grid every 1 / update_rate_hz
/// seconds (each end extrapolated along its velocity) and interpolates
/// linearly between grid points, so the rate must be well above the Doppler.
///
/// Determinism. Every draw is Philox4x32-10 (common/philox.hpp) under a key
/// derived from (stage seed, context.position), counter (tx, rx, sinusoid,
/// tag): a link's field is fixed for the run, whoever evaluates it, in any
/// order. Links fade independently of each other and of their reverse.
///
/// Cost: M sines/cosines per evaluation, at every grid point of every link
/// (and path) that carries a signal to a receiver that runs; the draws (M
/// Philox blocks, 2 M sines/cosines) once per link and path, kept by the stage
/// up to a memory bound (fading_stage.cpp), drawn again at each evaluation
/// beyond it.
#include <complex>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

enum class FadingModel { kRayleigh, kRician };

struct FadingSettings {
  FadingModel model = FadingModel::kRayleigh;
  double k_db = 6.0;              ///< Rician K: line-of-sight power over scattered power, dB
  std::uint32_t sinusoids = 32;   ///< M
  double update_rate_hz = 10000;  ///< the grid on which gains are computed
  std::uint64_t seed = 0;         ///< 0: the scenario's seed; otherwise this stage's own
};

const config::Fields<FadingSettings>& fading_fields();
ChannelStageComponent fading_component();

namespace fading {

/// One link-path's draws: each plane wave's departure and arrival directions
/// (cos, sin of the azimuth) and phase, and the line-of-sight wave's phase
/// (Rician, path 0 only). They depend only on (seed, stage position, tx, rx,
/// path), so the stage keeps them per link instead of drawing them again at
/// every evaluation (M Philox blocks and 2 M sines and cosines saved).
struct Waves {
  std::vector<std::complex<double>> departure;
  std::vector<std::complex<double>> arrival;
  std::vector<double> phase;
  std::optional<double> los_phase;
};

/// The draws of path `path` of the link tx_index -> rx_index. Pure.
Waves draw_waves(const FadingSettings& settings, std::uint64_t seed, std::size_t stage_position,
                 std::size_t tx_index, std::size_t rx_index, std::size_t path);

/// The gain h with the ends at tx.local and rx.local, from the link-path's
/// draws: bit for bit the gain below for the same link and path. Pure.
std::complex<double> gain(const FadingSettings& settings, double carrier_hz, const Waves& waves,
                          const LinkEnd& tx, const LinkEnd& rx);

/// The gain h of the link tx -> rx with its ends at tx.local and rx.local
/// (velocities are not read: the caller extrapolates). `seed` is the one in
/// force (settings.seed, or the scenario's when that is 0). Preconditions:
/// settings within their declared limits, carrier_hz > 0, node indices below
/// 2^32, path below 2^16. Pure, thread-safe.
std::complex<double> gain(const FadingSettings& settings, double carrier_hz, std::uint64_t seed,
                          std::size_t stage_position, const LinkEnd& tx, const LinkEnd& rx,
                          std::size_t path = 0);

}  // namespace fading
}  // namespace rfsitl::channel
