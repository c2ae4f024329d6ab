// The shadowing stage: its settings, declared once, and the stage that turns
// the field S (dB) into each link's amplitude.
#include <cmath>
#include <memory>

#include "rfsitl/channel/stages/shadowing.hpp"

namespace rfsitl::channel {

const config::Fields<ShadowingSettings>& shadowing_fields() {
  using S = ShadowingSettings;
  static const auto f =
      config::Fields<S>()
          .real("sigma_db", &S::sigma_db, "dB", {0.0, 30.0},
                "the shadowing's standard deviation (4-8 dB outdoors; 0 turns it off)")
          .real("decorrelation_m", &S::decorrelation_m, "m", {0.1, 1e5},
                "d: moving either end by r leaves exp(-r/d) of the correlation (Gudmundson)")
          .integer("sinusoids", &S::sinusoids, "", 4, 1024,
                   "M, sinusoids summed per link: more is more Gaussian, and costs M cosines "
                   "per link evaluation")
          .integer("seed", &S::seed, "", 0, UINT64_MAX,
                   "0: the scenario's seed; otherwise this stage's own draws");
  return f;
}

namespace {

class ShadowingStage final : public GainStage {
 public:
  ShadowingStage(const ShadowingSettings& s, std::uint64_t seed, std::size_t position)
      : s_(s), seed_(seed), position_(position) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    return std::pow(10.0, shadowing::field_db(s_, seed_, position_, link.tx, link.rx) / 20.0);
  }

  // The field belongs to the unordered pair (field_db orders the ends).
  bool reciprocal() const override { return true; }

 private:
  ShadowingSettings s_;
  std::uint64_t seed_;
  std::size_t position_;
};

}  // namespace

ChannelStageComponent shadowing_component() {
  return {shadowing_fields().info("channel", "shadowing",
                                  "log-normal shadowing, correlated over both ends' positions"),
          [](const config::Settings& settings, const StageContext& context) {
            const ShadowingSettings s = shadowing_fields().build(settings);
            return std::make_unique<ShadowingStage>(s, s.seed == 0 ? context.seed : s.seed,
                                                    context.position);
          }};
}

}  // namespace rfsitl::channel
