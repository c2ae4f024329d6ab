// The delay stage: its settings, declared once, and the stage that gives each
// link one path, late by its length over the speed of light.
#include "rfsitl/channel/stages/delay.hpp"

#include <cmath>
#include <memory>

#include "rfsitl/channel/radio.hpp"

namespace rfsitl::channel {

const config::Fields<DelaySettings>& delay_fields() {
  using S = DelaySettings;
  static const auto f =
      config::Fields<S>()
          .real("excess_ns", &S::excess_ns, "ns", {0.0, 1e7},
                "a fixed delay added to every link's d / c (cables, a repeater's latency)")
          .flag("whole_samples", &S::whole_samples,
                "round each delay to the nearest sample: one tap per link (a flat link's "
                "mixing cost) instead of up to 16, and an error of up to half a sample");
  return f;
}

namespace delay {

double seconds(const DelaySettings& settings, double distance_m, double sample_rate_hz) {
  const double s = distance_m / kSpeedOfLight + settings.excess_ns * 1e-9;
  if (!settings.whole_samples) return s;
  return std::round(s * sample_rate_hz) / sample_rate_hz;
}

}  // namespace delay

namespace {

class DelayStage final : public GainStage {
 public:
  DelayStage(const DelaySettings& s, double sample_rate_hz)
      : s_(s), sample_rate_hz_(sample_rate_hz) {}

  std::complex<double> gain(const LinkGeometry&) const override { return 1.0; }
  bool dispersive() const override { return true; }
  void paths(const LinkGeometry& link, std::vector<Path>& out) const override {
    out.push_back({delay::seconds(s_, link.distance_m, sample_rate_hz_), 1.0});
  }

 private:
  DelaySettings s_;
  double sample_rate_hz_;
};

}  // namespace

ChannelStageComponent delay_component() {
  return {delay_fields().info("channel", "delay", "propagation delay d / c, in fractional samples"),
          [](const config::Settings& settings, const StageContext& context) {
            return std::make_unique<DelayStage>(delay_fields().build(settings),
                                                context.sample_rate_hz);
          }};
}

}  // namespace rfsitl::channel
