// The multipath stage: its settings, declared once, and the stage that splits
// each link into the profile's taps.
#include <algorithm>
#include <memory>
#include <numbers>

#include "rfsitl/channel/stages/multipath.hpp"
#include "rfsitl/common/philox.hpp"

namespace rfsitl::channel {
namespace {

const config::RecordFields<MultipathTap>& tap_fields() {
  using T = MultipathTap;
  static const auto f =
      config::RecordFields<T>()
          .required("delay_ns", &T::delay_ns, "ns", {0.0, 1e6}, "after the link's first arrival")
          .required("gain_db", &T::gain_db, "dB", {-100.0, 30.0},
                    "the tap's power, relative to the others");
  return f;
}

}  // namespace

const config::Fields<MultipathSettings>& multipath_fields() {
  using S = MultipathSettings;
  static const auto f =
      config::Fields<S>()
          .choice("profile", &S::profile,
                  {{"tdl_a", MultipathProfile::kTdlA},
                   {"tdl_b", MultipathProfile::kTdlB},
                   {"tdl_c", MultipathProfile::kTdlC},
                   {"taps", MultipathProfile::kTaps}},
                  "tdl_a / tdl_b / tdl_c: TR 38.901's NLOS tapped delay lines (23, 23 and 24 "
                  "taps) scaled to delay_spread_ns; taps: the list in `taps`")
          .real("delay_spread_ns", &S::delay_spread_ns, "ns", {1.0, 1e5},
                "tdl_*: the RMS delay spread (38.901 Table 7.7.3-1: 10 very short, 30 short, "
                "100 nominal, 300 long, 1000 very long)")
          .records("taps", &S::taps, tap_fields(), 0, 64,
                   "profile taps: each path's delay and relative power")
          .integer("seed", &S::seed, "", 0, UINT64_MAX,
                   "0: the scenario's seed; otherwise this stage's own (the taps' phases)")
          .rule([](const S& s) {
            if (s.profile == MultipathProfile::kTaps && s.taps.empty()) {
              throw config::SettingError("taps", "profile taps needs at least one tap");
            }
            if (s.profile != MultipathProfile::kTaps && !s.taps.empty()) {
              throw config::SettingError("taps", "only with profile: taps");
            }
          });
  return f;
}

namespace {

constexpr std::uint32_t kTag = 0x4D504154;  // "MPAT": apart from other stages' counters

class MultipathStage final : public GainStage {
 public:
  MultipathStage(const MultipathSettings& s, std::uint64_t seed, std::size_t position)
      : paths_(multipath::normalised_paths(multipath::profile_taps(s))),
        key_(philox_subkey(seed, static_cast<std::uint32_t>(position), kTag)) {
    // Delays after the first arrival: the earliest tap defines the link's start.
    double first = paths_.front().delay_s;
    for (const Path& p : paths_) first = std::min(first, p.delay_s);
    for (Path& p : paths_) p.delay_s -= first;
  }

  // The profile's powers sum to 1.
  std::complex<double> gain(const LinkGeometry&) const override { return 1.0; }
  bool dispersive() const override { return true; }

  void paths(const LinkGeometry& link, std::vector<Path>& out) const override {
    // The unordered pair keys the phases: a reciprocal link.
    const auto a = static_cast<std::uint32_t>(std::min(link.tx.index, link.rx.index));
    const auto b = static_cast<std::uint32_t>(std::max(link.tx.index, link.rx.index));
    for (std::size_t i = 0; i < paths_.size(); ++i) {
      const PhiloxCounter u = philox4x32({a, b, static_cast<std::uint32_t>(i), kTag}, key_);
      const double phase = 2.0 * std::numbers::pi * static_cast<double>(u[0]) * 0x1.0p-32;
      out.push_back({paths_[i].delay_s, paths_[i].gain * std::polar(1.0, phase)});
    }
  }

 private:
  std::vector<Path> paths_;
  PhiloxKey key_{};
};

}  // namespace

ChannelStageComponent multipath_component() {
  return {multipath_fields().info("channel", "multipath",
                                  "a tapped delay line: TR 38.901 TDL-A/B/C or given taps, "
                                  "fractional delays"),
          [](const config::Settings& settings, const StageContext& context) {
            const MultipathSettings s = multipath_fields().build(settings);
            return std::make_unique<MultipathStage>(s, s.seed == 0 ? context.seed : s.seed,
                                                    context.position);
          }};
}

}  // namespace rfsitl::channel
