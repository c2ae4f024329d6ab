// The path_loss stage: its settings, declared once, and the stage that applies
// the chosen model to each link.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/channel/stages/tr36777.hpp"
#include "rfsitl/common/philox.hpp"

namespace rfsitl::channel {

const config::Fields<PathLossSettings>& path_loss_fields() {
  using S = PathLossSettings;
  static const auto f =
      config::Fields<S>()
          .choice("model", &S::model,
                  {{"paper", PathLossModel::kPaper},
                   {"free_space", PathLossModel::kFreeSpace},
                   {"log_distance", PathLossModel::kLogDistance},
                   {"two_ray", PathLossModel::kTwoRay},
                   {"tr36777_uma_av", PathLossModel::kTr36777UmaAv},
                   {"tr36777_umi_av", PathLossModel::kTr36777UmiAv}},
                  "paper: (1+j)/sqrt2 (d+1)^-paper_exponent; free_space: Friis; log_distance: "
                  "free space to d0, then 10 n log10(d/d0); two_ray: direct plus ground-reflected "
                  "ray (heights above channel.origin); tr36777_uma_av / tr36777_umi_av: 3GPP TR "
                  "36.777 urban macro / micro with aerial UEs (TR 38.901 UMa / UMi for UEs up to "
                  "22.5 m), mean loss without shadowing: the lower end of a link is the base "
                  "station, the higher the UE, their heights above channel.origin clamped to "
                  "1.5..300 m (the base station's to at most the UE's)")
          .real("paper_exponent", &S::paper_exponent, "", {0.0, 10.0},
                "paper: the amplitude's exponent (3 in the paper: power falls as d^-6)")
          .real("exponent", &S::exponent, "", {1.0, 10.0},
                "log_distance: n, the power's exponent beyond d0 (2 free space, 2.7-3.5 urban)")
          .real("reference_distance_m", &S::reference_distance_m, "m", {0.01, 1e4},
                "log_distance: d0, up to which the loss is free space's")
          .real("reflection", &S::reflection, "", {-1.0, 1.0},
                "two_ray: the ground's reflection coefficient (-1: a perfect conductor at grazing "
                "incidence)")
          .choice("los", &S::los,
                  {{"drawn", LineOfSight::kDrawn},
                   {"los", LineOfSight::kLos},
                   {"nlos", LineOfSight::kNlos}},
                  "tr36777_*: a link's line of sight. drawn: LOS with the model's probability "
                  "P_LOS(horizontal distance, UE height), one uniform draw per node pair (seeded, "
                  "fixed for the run, the same both ways); los / nlos: every link")
          .real("min_distance_m", &S::min_distance_m, "m", {0.01, 1e3},
                "shorter links count as this long (the far-field formulas diverge at 0; not paper; "
                "two_ray and tr36777_*: the horizontal distance)");
  return f;
}

namespace {

class PathLossStage final : public GainStage {
 public:
  PathLossStage(const PathLossSettings& s, const StageContext& context)
      : s_(s),
        carrier_hz_(context.carrier_hz),
        key_{static_cast<std::uint32_t>(context.seed),
             static_cast<std::uint32_t>(context.seed >> 32)},
        position_(static_cast<std::uint32_t>(context.position)) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    if (s_.model == PathLossModel::kPaper)
      return path_loss::paper_gain(link.distance_m, s_.paper_exponent);
    const double d = std::max(link.distance_m, s_.min_distance_m);
    switch (s_.model) {
      case PathLossModel::kFreeSpace:
        return from_db(-path_loss::free_space_db(d, carrier_hz_));
      case PathLossModel::kLogDistance:
        return from_db(
            -path_loss::log_distance_db(d, carrier_hz_, s_.exponent, s_.reference_distance_m));
      case PathLossModel::kTwoRay: {
        const double horizontal = std::max(link.horizontal_m, s_.min_distance_m);
        // The magnitude only: the carrier's phase over the path is the delay
        // stage's business, and a phase that jumps at every position update
        // would be no physics anyway.
        return std::abs(path_loss::two_ray_gain(horizontal, link.tx.local.z_m, link.rx.local.z_m,
                                                carrier_hz_, s_.reflection));
      }
      case PathLossModel::kTr36777UmaAv:
        return aerial_gain(link, path_loss::tr36777::Scenario::kUmaAv);
      case PathLossModel::kTr36777UmiAv:
        return aerial_gain(link, path_loss::tr36777::Scenario::kUmiAv);
      case PathLossModel::kPaper:
        break;
    }
    return 0.0;
  }

 private:
  static std::complex<double> from_db(double db) { return std::pow(10.0, db / 20.0); }

  /// TR 36.777: the lower end is the base station, the higher the aerial UE.
  /// Only min/max of the heights and the horizontal distance enter, and the
  /// draw is per unordered pair, so the gain is reciprocal.
  std::complex<double> aerial_gain(const LinkGeometry& link,
                                   path_loss::tr36777::Scenario scenario) const {
    namespace tr = path_loss::tr36777;
    const double low = std::min(link.tx.local.z_m, link.rx.local.z_m);
    const double high = std::max(link.tx.local.z_m, link.rx.local.z_m);
    const double h_ut = std::clamp(high, tr::kMinUtHeightM, tr::kMaxUtHeightM);
    // Not above the UE (a clamped UE could otherwise end up below it), and not
    // below 1.5 m, which keeps the breakpoint's effective height h - 1 m positive.
    const double h_bs = std::clamp(low, tr::kMinUtHeightM, h_ut);
    const double d2d = std::max(link.horizontal_m, s_.min_distance_m);
    bool los = s_.los == LineOfSight::kLos;
    if (s_.los == LineOfSight::kDrawn) {
      los = link_uniform(link.tx.index, link.rx.index) < tr::los_probability(scenario, d2d, h_ut);
    }
    return from_db(-tr::path_loss_db(scenario, los, d2d, h_bs, h_ut, carrier_hz_));
  }

  /// The link's fixed uniform in [0, 1): Philox under the scenario seed, at
  /// counter (lower index, higher index, stage position, tag). The tag keeps
  /// these counters apart from other draws under the same seed (the receivers'
  /// noise uses (sample pair, stream) with a small stream). Indices are below
  /// 2^32 (node counts are). 53 bits: every double in [0, 1) on the 2^-53 grid.
  double link_uniform(std::size_t a, std::size_t b) const {
    constexpr std::uint32_t kLosDrawTag = 0x4C4F5344;  // "LOSD"
    const PhiloxCounter w =
        philox4x32({static_cast<std::uint32_t>(std::min(a, b)),
                    static_cast<std::uint32_t>(std::max(a, b)), position_, kLosDrawTag},
                   key_);
    const std::uint64_t bits = (std::uint64_t{w[0]} << 21) | (w[1] >> 11);
    return static_cast<double>(bits) * 0x1.0p-53;
  }

  PathLossSettings s_;
  double carrier_hz_;
  PhiloxKey key_;
  std::uint32_t position_;
};

}  // namespace

ChannelStageComponent path_loss_component() {
  return {path_loss_fields().info("channel", "path_loss",
                                  "a link's loss from its length (and its ends' heights)"),
          [](const config::Settings& settings, const StageContext& context) {
            return std::make_unique<PathLossStage>(path_loss_fields().build(settings), context);
          }};
}

std::shared_ptr<const LinkBudget> make_paper_budget(double exponent) {
  // Checked here as well as by the declaration: a negative or NaN exponent
  // would make far nodes louder than near ones.
  if (!(exponent >= 0.0) || !std::isfinite(exponent)) {
    throw std::invalid_argument("paper path loss: exponent must be finite and >= 0");
  }
  PathLossSettings s;
  s.paper_exponent = exponent;
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(std::make_unique<PathLossStage>(s, StageContext{}));
  return std::make_shared<const LinkBudget>(0.0, std::move(stages));
}

}  // namespace rfsitl::channel
