// The fading stage: its settings, declared once, and the time-varying stage.
#include <memory>

#include "rfsitl/channel/stages/fading.hpp"

namespace rfsitl::channel {

const config::Fields<FadingSettings>& fading_fields() {
  using S = FadingSettings;
  static const auto f =
      config::Fields<S>()
          .choice("model", &S::model,
                  {{"rayleigh", FadingModel::kRayleigh}, {"rician", FadingModel::kRician}},
                  "rayleigh: scattered waves only; rician: plus a line-of-sight wave (k_db)")
          .real("k_db", &S::k_db, "dB", {-30.0, 40.0},
                "rician: K, the line-of-sight power over the scattered power")
          .integer("sinusoids", &S::sinusoids, "", 8, 1024,
                   "M, plane waves summed per link: more is more Gaussian, and costs M "
                   "sines and cosines per link and grid point")
          .real("update_rate_hz", &S::update_rate_hz, "Hz", {10.0, 1e8},
                "gains are computed this often and interpolated linearly between: keep it "
                "well above the Doppler (speed / wavelength)")
          .integer("seed", &S::seed, "", 0, UINT64_MAX,
                   "0: the scenario's seed; otherwise this stage's own draws");
  return f;
}

namespace {

class FadingStage final : public GainStage {
 public:
  FadingStage(const FadingSettings& s, double carrier_hz, std::uint64_t seed, std::size_t position)
      : s_(s), carrier_hz_(carrier_hz), seed_(seed), position_(position) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    return fading::gain(s_, carrier_hz_, seed_, position_, link.tx, link.rx, link.path);
  }

  bool reciprocal() const override { return false; }
  bool time_varying() const override { return true; }
  double update_interval_s() const override { return 1.0 / s_.update_rate_hz; }

 private:
  FadingSettings s_;
  double carrier_hz_;
  std::uint64_t seed_;
  std::size_t position_;
};

}  // namespace

ChannelStageComponent fading_component() {
  return {fading_fields().info("channel", "fading",
                               "Rayleigh or Rician fast fading; its Doppler follows the nodes' "
                               "velocities"),
          [](const config::Settings& settings, const StageContext& context) {
            const FadingSettings s = fading_fields().build(settings);
            return std::make_unique<FadingStage>(
                s, context.carrier_hz, s.seed == 0 ? context.seed : s.seed, context.position);
          }};
}

}  // namespace rfsitl::channel
