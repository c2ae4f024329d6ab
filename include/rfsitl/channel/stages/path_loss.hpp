#pragma once
/// The path_loss stage: a link's loss from its length (and its ends' heights),
/// by one of several models. The formulas are pure functions, tested against
/// their textbook forms; the stage picks one by its `model` setting.
#include <complex>
#include <memory>
#include <string>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/channel/radio.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

enum class PathLossModel {
  kPaper,
  kFreeSpace,
  kLogDistance,
  kTwoRay,
  kTr36777UmaAv,  ///< 3GPP TR 36.777 urban macro with aerial UEs (TR 38.901 UMa up to 22.5 m)
  kTr36777UmiAv,  ///< 3GPP TR 36.777 urban micro with aerial UEs (TR 38.901 UMi up to 22.5 m)
};

/// The TR 36.777 models' line-of-sight state of a link.
enum class LineOfSight {
  /// LOS iff u < P_LOS(d2D, h_UT), u uniform in [0, 1) from Philox keyed by the
  /// scenario seed, counter (lower node index, higher node index, stage
  /// position): one u per link for the whole run, the same both ways and in any
  /// evaluation order. A link turns NLOS or LOS only as P_LOS moves past its u.
  kDrawn,
  kLos,   ///< every link in line of sight
  kNlos,  ///< no link in line of sight
};

struct PathLossSettings {
  PathLossModel model = PathLossModel::kPaper;
  double paper_exponent = 3.0;        ///< paper: on the amplitude, c ~ (d + 1)^-e
  double exponent = 3.0;              ///< log_distance: on the power, 10 n log10(d / d0)
  double reference_distance_m = 1.0;  ///< log_distance: d0, where the loss is free space's
  double reflection = -1.0;           ///< two_ray: the ground's reflection coefficient
  /// tr36777_*: how a link's LOS state is chosen.
  LineOfSight los = LineOfSight::kDrawn;
  double min_distance_m = 1.0;  ///< shorter links count as this long (not paper)
};

const config::Fields<PathLossSettings>& path_loss_fields();
ChannelStageComponent path_loss_component();

/// The paper's channel alone: path_loss (model paper, this exponent) at 0 dBm.
/// Throws std::invalid_argument unless exponent is finite and >= 0.
std::shared_ptr<const LinkBudget> make_paper_budget(double exponent = 3.0);

namespace path_loss {

/// The RF-SITL paper's amplitude: (1+j)/sqrt2 (d + 1)^-exponent, evaluated in
/// double. |.|^2 = (d + 1)^(-2 exponent): exactly 1 at d = 0.
std::complex<double> paper_gain(double d_m, double exponent);

/// Friis free-space loss in dB: 20 log10(4 pi d f / c). Preconditions: d, f > 0.
double free_space_db(double d_m, double carrier_hz);

/// Log-distance loss in dB: free_space_db(d0) + 10 n log10(d / d0).
double log_distance_db(double d_m, double carrier_hz, double exponent, double d0_m);

/// Two-ray ground reflection, exact (Rappaport 4.6; Goldsmith 2.4): the direct
/// ray and one reflected off a flat ground with coefficient `reflection`,
///   g = lambda / (4 pi) * (e^{-j k r1} / r1 + reflection e^{-j k r2} / r2),
/// r1 = sqrt(d^2 + (ht - hr)^2), r2 = sqrt(d^2 + (ht + hr)^2), d horizontal,
/// k = 2 pi / lambda. Beyond the crossover distance |g|^2 falls as
/// (ht hr)^2 / d^4 (for reflection -1). Heights below the ground count as 0.
std::complex<double> two_ray_gain(double horizontal_m, double h_tx_m, double h_rx_m,
                                  double carrier_hz, double reflection);

/// The two-ray critical distance 4 ht hr / lambda (Goldsmith's d_c): the last
/// peak of the two rays' interference, where the path difference is half a
/// wavelength. Beyond it the gain falls monotonically, towards the d^-4 law.
double two_ray_crossover_m(double h_tx_m, double h_rx_m, double carrier_hz);

}  // namespace path_loss
}  // namespace rfsitl::channel
