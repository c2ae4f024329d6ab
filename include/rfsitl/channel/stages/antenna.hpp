#pragma once
/// The antenna stage: every node carries the same antenna, fixed to its
/// airframe, so a link's gain depends on where each body points.
///
/// Model. gain(tx -> rx) = G(direction of rx in tx's body frame)
///                        + G(direction of tx in rx's body frame), in dB;
/// the amplitude factor is 10^(dB / 20), real. Directions and attitudes are
/// body_frame.hpp's: a node without an attitude is level and faces north. A
/// node's link to itself, or to a node at the same place (no direction), has
/// 0 dB. The stage re-evaluates a node's links when it turns
/// (depends_on_attitude). It declares itself not reciprocal, as antennas that
/// point somewhere are in general; with one antenna type on every node the sum
/// above is in fact symmetric in tx and rx (the reciprocity theorem).
///
/// Patterns (`pattern`), gain_dbi = the peak (0: the pattern's standard one):
///  - omni: G = gain_dbi everywhere (0 dBi by default).
///  - dipole: the half-wave dipole, G = peak + 20 log10(cos(pi/2 cos t) / sin t),
///    t the angle from the dipole's axis (`boresight`), peak 2.15 dBi by
///    default (a half-wave dipole's directivity, 1.64). The nulls along the axis
///    are floored at peak - 40 dB (kDipoleNullFloorDb): real dipoles' nulls are
///    filled to -20..-30 dB by the feed and the airframe, and the floor keeps
///    the gain finite.
///  - patch: 3GPP TR 38.901 (V14 on) Table 7.3-1, the antenna element pattern:
///      A_v = -min(12 ((theta - 90) / 65)^2, 30), A_h = -min(12 (phi / 65)^2, 30),
///      G = peak - min(-(A_v + A_h), 30) dB, peak 8 dBi by default,
///    theta the zenith angle from the antenna's vertical (deg), phi the azimuth
///    from its boresight (deg, [-180, 180]); 65 deg half-power beamwidths, 30 dB
///    front-to-back. The antenna's vertical is the body's up (-z) for a
///    boresight in the body's x-y plane, and the body's forward (x) for a
///    boresight along z (down or up).
///  - file: a gain table (below); gain_dbi must be 0 (the table is in dBi).
///
/// `boresight`: the body axis the patch faces, or the dipole lies along. The
/// default is down: a patch on a UAV's belly faces the ground station and the
/// other vehicles below and around it, with the airframe behind it; and a
/// dipole along z is vertical when the body is level (a whip or sleeve dipole
/// hanging under the fuselage), so it radiates most towards the horizon.
///
/// Pattern file (`file`, relative to the scenario's folder):
///   # a '#' line is a comment; blank lines are skipped
///   el\az, 0, 90, 180, 270, 360
///   -90,  -15, -22, -22, -22, -15
///   0,      8, -15, -22, -15,   8
///   90,   -15, -22, -22, -22, -15
/// (the patch above facing forward, every 90 deg). A CSV grid of gains in
/// dBi (finite, in [-200, 100]) over the body frame's azimuth x elevation
/// (body_frame.hpp's angles, degrees). The first row:
/// a label cell (not read), then the azimuths, strictly increasing, from 0 to
/// at most 360. Every other row: its elevation, then one gain per azimuth.
/// The elevations increase strictly from -90 to 90. At least 2 azimuths and 2
/// elevations. Azimuth wraps at 360: past the last column the gain is
/// interpolated towards column 0 (a last column at 360 must equal column 0).
/// Between grid points the gain is interpolated bilinearly in dB. Cells are
/// decimal numbers (spaces around them are ignored); lines may end in CRLF.
/// At most kMaxPatternBytes (1 MiB). `boresight` is not used: the table
/// says it all. A file that breaks any of this is refused when the stage is
/// built, with "<file>:<line>: <reason>".
#include <complex>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/channel/body_frame.hpp"
#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

enum class AntennaPattern { kOmni, kDipole, kPatch, kFile };
enum class BodyAxis { kForward, kBackward, kRight, kLeft, kDown, kUp };

struct AntennaSettings {
  AntennaPattern pattern = AntennaPattern::kOmni;
  std::string file;       ///< the pattern file, with pattern file
  double gain_dbi = 0.0;  ///< the peak; 0: the pattern's standard peak
  BodyAxis boresight = BodyAxis::kDown;
};

const config::Fields<AntennaSettings>& antenna_fields();
ChannelStageComponent antenna_component();

namespace antenna {

constexpr double kDipolePeakDbi = 2.15;
constexpr double kPatchPeakDbi = 8.0;
constexpr double kDipoleNullFloorDb = -40.0;
constexpr std::size_t kMaxPatternBytes = std::size_t{1} << 20;

/// The unit body vector along `axis`.
BodyVector axis_vector(BodyAxis axis);

/// The half-wave dipole's gain in dBi at angle t from its axis, given
/// cos t in [-1, 1]: peak + max(20 log10(cos(pi/2 cos t) / sin t), kDipoleNullFloorDb).
double dipole_gain_dbi(double peak_dbi, double cos_from_axis);

/// TR 38.901's element pattern in dBi at zenith angle `zenith_deg` in [0, 180]
/// and azimuth `azimuth_deg` in [-180, 180] of the antenna's own frame.
double patch_gain_dbi(double peak_dbi, double zenith_deg, double azimuth_deg);

/// A gain table over body azimuth x elevation (the pattern file's grid).
class PatternGrid {
 public:
  /// Precondition: what parse_pattern checks; the last azimuth is 360.
  PatternGrid(std::vector<double> azimuths_deg, std::vector<double> elevations_deg,
              std::vector<double> gains_dbi);

  /// The gain in dBi at azimuth [0, 360) and elevation [-90, 90] (clamped),
  /// interpolated bilinearly. Thread-safe (const).
  double gain_dbi(double azimuth_deg, double elevation_deg) const;

  const std::vector<double>& azimuths_deg() const { return azimuths_; }
  const std::vector<double>& elevations_deg() const { return elevations_; }
  /// The gain at grid point (elevation row, azimuth column), row-major.
  double at(std::size_t row, std::size_t column) const {
    return gains_[row * azimuths_.size() + column];
  }

 private:
  std::vector<double> azimuths_;
  std::vector<double> elevations_;
  std::vector<double> gains_;
};

/// The pattern file's text as a grid, a 360 column appended when the file
/// stops short of it. Throws std::invalid_argument "<name>:<line>: <reason>"
/// for a text that breaks the format (antenna.hpp's comment), and nothing else.
PatternGrid parse_pattern(std::string_view text, const std::string& name);

/// parse_pattern on the file at `path`, also throwing std::invalid_argument
/// "<path>: ..." when it cannot be read.
PatternGrid load_pattern(const std::string& path);

}  // namespace antenna
}  // namespace rfsitl::channel
