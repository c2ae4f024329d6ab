// The antenna stage: its settings, declared once, and the stage that adds both
// ends' gains towards each other.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>

#include "rfsitl/channel/stages/antenna.hpp"

namespace rfsitl::channel {

const config::Fields<AntennaSettings>& antenna_fields() {
  using S = AntennaSettings;
  static const auto f =
      config::Fields<S>()
          .choice("pattern", &S::pattern,
                  {{"omni", AntennaPattern::kOmni},
                   {"dipole", AntennaPattern::kDipole},
                   {"patch", AntennaPattern::kPatch},
                   {"file", AntennaPattern::kFile}},
                  "omni; dipole (half-wave); patch (TR 38.901 element, 65 deg beams); "
                  "file (a gain table over body azimuth x elevation)")
          .text("file", &S::file,
                "with pattern file: the CSV gain table, relative to the scenario's folder")
          .real("gain_dbi", &S::gain_dbi, "dBi", {-50.0, 50.0},
                "the peak gain; 0: the pattern's standard one (omni 0, dipole 2.15, patch 8); "
                "must be 0 with pattern file")
          .choice("boresight", &S::boresight,
                  {{"forward", BodyAxis::kForward},
                   {"backward", BodyAxis::kBackward},
                   {"right", BodyAxis::kRight},
                   {"left", BodyAxis::kLeft},
                   {"down", BodyAxis::kDown},
                   {"up", BodyAxis::kUp}},
                  "the body axis the patch faces or the dipole lies along (down: a belly "
                  "patch, a vertical dipole)")
          .rule([](const S& s) {
            const bool from_file = s.pattern == AntennaPattern::kFile;
            if (from_file && s.file.empty()) {
              throw config::SettingError("file", "pattern file needs a file");
            }
            if (!from_file && !s.file.empty()) {
              throw config::SettingError("file", "is read only with pattern file");
            }
            if (from_file && s.gain_dbi != 0.0) {
              throw config::SettingError("gain_dbi",
                                         "must be 0 with pattern file (its gains are dBi)");
            }
          });
  return f;
}

namespace {

/// The antenna's own axes in the body frame: boresight b, vertical u (the
/// zenith of TR 38.901's pattern) and h completing them (its sign does not
/// matter: the pattern is symmetric in azimuth).
struct AntennaFrame {
  BodyVector boresight;
  BodyVector vertical;
  BodyVector horizontal;
};

AntennaFrame frame_of(BodyAxis axis) {
  const BodyVector b = antenna::axis_vector(axis);
  const bool along_z = axis == BodyAxis::kDown || axis == BodyAxis::kUp;
  const BodyVector u = along_z ? BodyVector{1.0, 0.0, 0.0} : BodyVector{0.0, 0.0, -1.0};
  const BodyVector h{u.right * b.down - u.down * b.right, u.down * b.forward - u.forward * b.down,
                     u.forward * b.right - u.right * b.forward};
  return {b, u, h};
}

double standard_peak_dbi(AntennaPattern pattern) {
  switch (pattern) {
    case AntennaPattern::kDipole:
      return antenna::kDipolePeakDbi;
    case AntennaPattern::kPatch:
      return antenna::kPatchPeakDbi;
    case AntennaPattern::kOmni:
    case AntennaPattern::kFile:
      break;
  }
  return 0.0;
}

class AntennaStage final : public GainStage {
 public:
  AntennaStage(const AntennaSettings& s, std::optional<antenna::PatternGrid> grid)
      : pattern_(s.pattern),
        peak_dbi_(s.gain_dbi != 0.0 ? s.gain_dbi : standard_peak_dbi(s.pattern)),
        frame_(frame_of(s.boresight)),
        grid_(std::move(grid)) {}

  std::complex<double> gain(const LinkGeometry& link) const override {
    if (link.tx.index == link.rx.index) return 1.0;
    const double db = end_gain_dbi(link.tx, link.rx) + end_gain_dbi(link.rx, link.tx);
    return std::pow(10.0, db / 20.0);
  }

  bool reciprocal() const override { return false; }
  bool depends_on_attitude() const override { return true; }

 private:
  /// `from`'s gain towards `to`, dBi (0 when they coincide).
  double end_gain_dbi(const LinkEnd& from, const LinkEnd& to) const {
    const std::optional<BodyVector> d = direction_in_body(from, to);
    if (!d) return 0.0;
    switch (pattern_) {
      case AntennaPattern::kDipole:
        return antenna::dipole_gain_dbi(peak_dbi_, dot(*d, frame_.boresight));
      case AntennaPattern::kPatch: {
        const double zenith_deg =
            std::acos(std::clamp(dot(*d, frame_.vertical), -1.0, 1.0)) * 180.0 / std::numbers::pi;
        const double azimuth_deg =
            std::atan2(dot(*d, frame_.horizontal), dot(*d, frame_.boresight)) * 180.0 /
            std::numbers::pi;
        return antenna::patch_gain_dbi(peak_dbi_, zenith_deg, azimuth_deg);
      }
      case AntennaPattern::kFile:
        return grid_->gain_dbi(azimuth_deg(*d), elevation_deg(*d));
      case AntennaPattern::kOmni:
        break;
    }
    return peak_dbi_;
  }

  AntennaPattern pattern_;
  double peak_dbi_;
  AntennaFrame frame_;
  std::optional<antenna::PatternGrid> grid_;
};

}  // namespace

ChannelStageComponent antenna_component() {
  return {antenna_fields().info("channel", "antenna",
                                "each end's antenna gain towards the other, from where its body "
                                "points"),
          [](const config::Settings& settings, const StageContext& context) {
            const AntennaSettings s = antenna_fields().build(settings);
            std::optional<antenna::PatternGrid> grid;
            if (s.pattern == AntennaPattern::kFile) {
              const std::filesystem::path path = std::filesystem::path(context.source_dir) / s.file;
              grid = antenna::load_pattern(path.string());
            }
            return std::make_unique<AntennaStage>(s, std::move(grid));
          }};
}

}  // namespace rfsitl::channel
