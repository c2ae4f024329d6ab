// The antenna stage: the body-frame rotation against vectors turned by hand and
// against the three elementary rotations composed; each pattern's gain at
// given attitudes against its formula (written out here) or the table's
// values; turning a node; and the pattern file's refusals, each at file:line.
#include "rfsitl/channel/stages/antenna.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "rfsitl/registry/channel_stage_registry.hpp"

#include "stage_test_support.hpp"

namespace rfsitl::channel {
namespace {

using rfsitl::testing::end;
using rfsitl::testing::link;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const std::string kPatchFile = "patterns/patch_8dbi.csv";  // under scenarios/

/// An end 100 m from `from` at world azimuth `az_deg` (clockwise from north)
/// and elevation `el_deg`.
LinkEnd end_towards(std::size_t index, const LinkEnd& from, double az_deg, double el_deg,
                    std::optional<Orientation> attitude = std::nullopt) {
  const double r = 100.0;
  return end(index, from.local.x_m + r * std::cos(el_deg * kDeg) * std::sin(az_deg * kDeg),
             from.local.y_m + r * std::cos(el_deg * kDeg) * std::cos(az_deg * kDeg),
             from.local.z_m + r * std::sin(el_deg * kDeg), attitude);
}

Orientation attitude_deg(double roll, double pitch, double yaw) {
  return {roll * kDeg, pitch * kDeg, yaw * kDeg};
}

config::Settings settings(const std::string& pattern, const std::string& boresight = "down",
                          double gain_dbi = 0.0, const std::string& file = "") {
  config::Settings s = find_channel_stage("antenna")->info.defaults();
  s.set("pattern", pattern);
  s.set("boresight", boresight);
  s.set("gain_dbi", gain_dbi);
  s.set("file", file);
  return s;
}

std::unique_ptr<GainStage> make_stage(const config::Settings& s,
                                      const std::string& source_dir = RFSITL_SOURCE_DIR
                                      "/scenarios") {
  const ChannelStageComponent* c = find_channel_stage("antenna");
  c->info.validate(s);
  return c->make(s, StageContext{2.4e9, 1, 0, source_dir, {}});
}

double gain_db(const GainStage& st, const LinkEnd& tx, const LinkEnd& rx) {
  return 20.0 * std::log10(std::abs(st.gain(link(tx, rx))));
}

/// TR 38.901 Table 7.3-1, written out: theta zenith and phi azimuth in degrees.
double patch_formula(double theta, double phi) {
  const double a_v = -std::min(12.0 * std::pow((theta - 90.0) / 65.0, 2.0), 30.0);
  const double a_h = -std::min(12.0 * std::pow(phi / 65.0, 2.0), 30.0);
  return 8.0 - std::min(-(a_v + a_h), 30.0);
}

/// The half-wave dipole, 2.15 dBi peak, t from its axis in degrees.
double dipole_formula(double t) {
  return 2.15 + 20.0 * std::log10(std::cos(kPi / 2.0 * std::cos(t * kDeg)) / std::sin(t * kDeg));
}

void expect_body(const EnuVector& v, std::optional<Orientation> a, double f, double r, double d) {
  const BodyVector b = to_body(v, a);
  EXPECT_NEAR(b.forward, f, 1e-12);
  EXPECT_NEAR(b.right, r, 1e-12);
  EXPECT_NEAR(b.down, d, 1e-12);
}

// ---- the rotation -------------------------------------------------------------------

TEST(AntennaBodyFrame, KnownAttitudesTurnKnownVectors) {
  // No attitude: level, facing north.
  expect_body({0, 1, 0}, std::nullopt, 1, 0, 0);
  expect_body({1, 0, 0}, std::nullopt, 0, 1, 0);
  expect_body({0, 0, 1}, std::nullopt, 0, 0, -1);
  // Yaw 90: facing east, north is on the left.
  expect_body({1, 0, 0}, attitude_deg(0, 0, 90), 1, 0, 0);
  expect_body({0, 1, 0}, attitude_deg(0, 0, 90), 0, -1, 0);
  // Pitch 30 nose up: the nose points north 30 deg up; up is ahead and above.
  const double c30 = std::sqrt(3.0) / 2.0;
  expect_body({0, c30, 0.5}, attitude_deg(0, 30, 0), 1, 0, 0);
  expect_body({0, 0, 1}, attitude_deg(0, 30, 0), 0.5, 0, -c30);
  // Roll 90 right wing down: the ground is to the right, the top faces east.
  expect_body({0, 0, -1}, attitude_deg(90, 0, 0), 0, 1, 0);
  expect_body({1, 0, 0}, attitude_deg(90, 0, 0), 0, 0, -1);
  // Yaw 90 then pitch 45: the nose points east, 45 deg up.
  const double h = std::sqrt(0.5);
  expect_body({h, 0, h}, attitude_deg(0, 45, 90), 1, 0, 0);
}

TEST(AntennaBodyFrame, MatchesTheElementaryRotationsComposed) {
  // Body = Rx(roll)^T Ry(pitch)^T Rz(yaw)^T NED, each passive rotation by hand.
  for (const Orientation a : {attitude_deg(10, -20, 30), attitude_deg(-170, 80, 250),
                              attitude_deg(45, 45, -45), attitude_deg(5, -89, 181)}) {
    for (const EnuVector v : {EnuVector{1, 2, 3}, EnuVector{-4, 0.5, -2}, EnuVector{0, 0, -7}}) {
      double x = v.north, y = v.east, z = -v.up;
      const double x1 = std::cos(a.yaw_rad) * x + std::sin(a.yaw_rad) * y;
      const double y1 = -std::sin(a.yaw_rad) * x + std::cos(a.yaw_rad) * y;
      x = x1;
      y = y1;
      const double x2 = std::cos(a.pitch_rad) * x - std::sin(a.pitch_rad) * z;
      const double z2 = std::sin(a.pitch_rad) * x + std::cos(a.pitch_rad) * z;
      x = x2;
      z = z2;
      const double y3 = std::cos(a.roll_rad) * y + std::sin(a.roll_rad) * z;
      const double z3 = -std::sin(a.roll_rad) * y + std::cos(a.roll_rad) * z;
      expect_body(v, a, x, y3, z3);
    }
  }
}

TEST(AntennaBodyFrame, AnglesOfBodyDirections) {
  EXPECT_NEAR(azimuth_deg({0, 1, 0}), 90.0, 1e-12);
  EXPECT_NEAR(azimuth_deg({0, -1, 0}), 270.0, 1e-12);
  EXPECT_NEAR(azimuth_deg({-1, -1e-300, 0}), 180.0, 1e-12);
  EXPECT_NEAR(elevation_deg({0, 0, 1}), -90.0, 1e-12);
  EXPECT_NEAR(elevation_deg({std::sqrt(0.5), 0, -std::sqrt(0.5)}), 45.0, 1e-12);
}

// ---- the patterns -------------------------------------------------------------------

TEST(AntennaOmni, ConstantGainAtEachEnd) {
  const auto omni0 = make_stage(settings("omni"));
  const auto omni3 = make_stage(settings("omni", "down", 3.0));
  const LinkEnd a = end(0, 0, 0, 10, attitude_deg(20, 30, 40));
  const LinkEnd b = end(1, 300, -50, 90);
  EXPECT_NEAR(gain_db(*omni0, a, b), 0.0, 1e-12);
  EXPECT_NEAR(gain_db(*omni3, a, b), 6.0, 1e-12);
  EXPECT_DOUBLE_EQ(std::abs(omni3->gain(link(a, a))), 1.0);  // the diagonal
}

TEST(AntennaDipole, BroadsideAtThePeakNullAlongTheAxis) {
  const auto dipole = make_stage(settings("dipole"));  // vertical when level
  const LinkEnd a = end(0, 0, 0, 50);
  EXPECT_NEAR(gain_db(*dipole, a, end(1, 200, 100, 50)), 2 * 2.15, 1e-9);
  EXPECT_NEAR(gain_db(*dipole, a, end(1, 0, 0, 150)), 2 * (2.15 - 40.0), 1e-9);  // the floor
  // 30 deg above the horizon is 60 deg from the axis, at both ends.
  EXPECT_NEAR(gain_db(*dipole, a, end_towards(1, a, 70, 30)), 2 * dipole_formula(60), 1e-9);
  EXPECT_NEAR(2 * dipole_formula(60),
              2 * (2.15 + 20 * std::log10(std::sqrt(0.5) / (std::sqrt(3.0) / 2))), 1e-12);
  // Rolled 90 deg (right wing down), the dipole lies east-west: the ground
  // below is broadside to it (the level end below looks up its own axis), the
  // east is along it, the north broadside.
  const LinkEnd rolled = end(0, 0, 0, 50, attitude_deg(90, 0, 0));
  EXPECT_NEAR(gain_db(*dipole, rolled, end(1, 0, 0, 0)), 2.15 + (2.15 - 40.0), 1e-9);
  EXPECT_NEAR(gain_db(*dipole, rolled, end(1, 100, 0, 50)), (2.15 - 40.0) + 2.15, 1e-9);
  EXPECT_NEAR(gain_db(*dipole, rolled, end(1, 0, 100, 50)), 2.15 + 2.15, 1e-9);
}

TEST(AntennaPatch, FacingDownTheUpperEndHasThePeakTheLowerItsBack) {
  const auto patch = make_stage(settings("patch"));
  EXPECT_NEAR(gain_db(*patch, end(0, 0, 0, 100), end(1, 0, 0, 0)), 8.0 + (8.0 - 30.0), 1e-9);
}

// A forward patch on A (yaw 30) sees B at body azimuth 45, elevation 15; B,
// facing back at A (yaw 255), sees A straight ahead, 15 deg down.
TEST(AntennaPatch, GainAtGivenAttitudesIsTheFormulas) {
  const auto patch = make_stage(settings("patch", "forward"));
  const LinkEnd a = end(0, 0, 0, 50, attitude_deg(0, 0, 30));
  const LinkEnd b = end_towards(1, a, 75, 15, attitude_deg(0, 0, 255));
  EXPECT_NEAR(gain_db(*patch, a, b), patch_formula(90 - 15, 45) + patch_formula(90 + 15, 0), 1e-9);
  // A patch with a 5 dBi peak: both ends 3 dB lower.
  EXPECT_NEAR(gain_db(*make_stage(settings("patch", "forward", 5.0)), a, b),
              patch_formula(75, 45) + patch_formula(105, 0) - 6.0, 1e-9);
}

TEST(AntennaFile, GainAtGivenAttitudesIsTheTables) {
  const auto table = make_stage(settings("file", "down", 0.0, kPatchFile));
  // Grid points: the table's cells (el 15, az 45) and (el -15, az 0).
  const LinkEnd a = end(0, 0, 0, 50, attitude_deg(0, 0, 30));
  const LinkEnd b = end_towards(1, a, 75, 15, attitude_deg(0, 0, 255));
  EXPECT_NEAR(gain_db(*table, a, b), 1.61 + 7.36, 1e-9);
  // ... which are the formula's values, rounded to 0.01 dB.
  EXPECT_NEAR(1.61, patch_formula(75, 45), 0.005);
  EXPECT_NEAR(7.36, patch_formula(105, 0), 0.005);
  // Between grid points, bilinear: A (level, yaw 0) sees C at az 50, el 20,
  // a third of the way from az 45 to 60 and from el 15 to 30. C pitched 5 deg
  // down and facing A sees A at az 0, el -15 (a grid point again).
  const LinkEnd level = end(0, 0, 0, 50);
  const LinkEnd c = end_towards(1, level, 50, 20, attitude_deg(0, -5, 230));
  const double el15 = 1.61 + (-2.86 - 1.61) / 3.0;   // az 50 on the el 15 row
  const double el30 = -0.31 + (-4.78 + 0.31) / 3.0;  // az 50 on the el 30 row
  EXPECT_NEAR(gain_db(*table, level, c), el15 + (el30 - el15) / 3.0 + 7.36, 1e-9);
}

// ---- attitude and reciprocity -------------------------------------------------------

TEST(AntennaStage, TurningANodeChangesTheLinkAsPredicted) {
  const auto patch = make_stage(settings("patch", "forward"));
  const LinkEnd b = end(1, 0, 100, 50, attitude_deg(0, 0, 180));  // faces A
  const LinkEnd facing = end(0, 0, 0, 50);                        // faces B
  EXPECT_NEAR(gain_db(*patch, facing, b), 16.0, 1e-9);
  // Yaw 90: B is now at A's left, 90 deg off boresight: 12 (90 / 65)^2 dB down.
  const LinkEnd turned = end(0, 0, 0, 50, attitude_deg(0, 0, 90));
  EXPECT_NEAR(gain_db(*patch, turned, b), 8.0 - 12.0 * (90.0 / 65.0) * (90.0 / 65.0) + 8.0, 1e-9);
  // A dipole along the nose: B on the axis, then broadside after the turn.
  const auto dipole = make_stage(settings("dipole", "forward"));
  EXPECT_NEAR(gain_db(*dipole, facing, b), 2 * (2.15 - 40.0), 1e-9);
  EXPECT_NEAR(gain_db(*dipole, turned, b), 2.15 + (2.15 - 40.0), 1e-9);
}

TEST(AntennaStage, NoAttitudeIsLevelFacingNorth) {
  const auto patch = make_stage(settings("patch", "forward"));
  const LinkEnd b = end(1, 40, 100, 80, attitude_deg(3, 4, 5));
  EXPECT_EQ(patch->gain(link(end(0, 0, 0, 50), b)),
            patch->gain(link(end(0, 0, 0, 50, Orientation{}), b)));
}

TEST(AntennaStage, EachEndAddsItsOwnGainAndDeclaresItselfNonReciprocal) {
  const auto patch = make_stage(settings("patch", "forward"));
  EXPECT_FALSE(patch->reciprocal());
  EXPECT_TRUE(patch->depends_on_attitude());
  // A faces B (8 dBi); B faces away from A (8 - 30 dBi): unequal ends.
  const LinkEnd a = end(0, 0, 0, 50);
  const LinkEnd b = end(1, 0, 100, 50);
  EXPECT_NEAR(gain_db(*patch, a, b), 8.0 + (8.0 - 30.0), 1e-9);
  // With one antenna type on both ends the reverse link sums the same two
  // gains (the reciprocity theorem): the flag only costs an evaluation.
  EXPECT_NEAR(gain_db(*patch, b, a), 8.0 + (8.0 - 30.0), 1e-9);
}

// ---- the pattern file ---------------------------------------------------------------

/// The message of parse_pattern's refusal of `text`, or "(accepted)".
std::string refusal(const std::string& text) {
  try {
    antenna::parse_pattern(text, "pattern.csv");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

void expect_refused_at(const std::string& text, int line) {
  const std::string prefix = "pattern.csv:" + std::to_string(line) + ": ";
  EXPECT_EQ(refusal(text).rfind(prefix, 0), 0u) << refusal(text);
}

TEST(AntennaPatternFile, BrokenFilesAreRefusedAtTheirLine) {
  const std::string head = "el\\az,0,180,360\n-90,1,2,1\n";
  expect_refused_at(head + "0,1,2\n90,1,2,1\n", 3);            // a missing cell
  expect_refused_at(head + "0,1,,1\n90,1,2,1\n", 3);           // an empty cell
  expect_refused_at(head + "0,1,2,1,\n90,1,2,1\n", 3);         // one cell too many
  expect_refused_at(head + "# c\n\n0,1,abc,1\n", 5);           // not a number
  expect_refused_at(head + "0,1,nan,1\n", 3);                  // not finite
  expect_refused_at(head + "0,1,1e999,1\n", 3);                // overflows
  expect_refused_at(head + "0,1,500,1\n", 3);                  // beyond 100 dBi
  expect_refused_at("el,0,180,90\n-90,1,2,3\n90,1,2,3\n", 1);  // azimuths go back
  expect_refused_at("el,10,180\n-90,1,2\n90,1,2\n", 1);        // start past 0
  expect_refused_at("el,0,400\n-90,1,2\n90,1,2\n", 1);         // end past 360
  expect_refused_at("el,0\n-90,1\n90,1\n", 1);                 // one azimuth
  expect_refused_at(head + "10,1,2,1\n0,1,2,1\n", 4);          // elevations go back
  expect_refused_at("el,0,180\n-80,1,2\n90,1,2\n", 2);         // start above -90
  expect_refused_at(head + "60,1,2,1\n", 3);                   // end below 90
  expect_refused_at(head, 2);                                  // one elevation row
  expect_refused_at(head + "90,1,2,3\n", 3);                   // 360 is not 0 again
  expect_refused_at("# only a comment\n", 1);                  // no header
  expect_refused_at("", 1);
  // Over 1 MiB: refused on the line where the limit is crossed (the third).
  expect_refused_at("el,0,360\n# c\n#" + std::string(antenna::kMaxPatternBytes, 'x'), 3);
}

TEST(AntennaPatternFile, CommentsBlankLinesCrlfAndAzimuthWrap) {
  // Columns stop at 270: 270..360 interpolates towards column 0.
  const antenna::PatternGrid g = antenna::parse_pattern(
      "# a comment\r\n\r\n el\\az , 0, 90 ,180,270\r\n-90,0,0,0,0\r\n90,4,8,12,16\r\n",
      "pattern.csv");
  EXPECT_DOUBLE_EQ(g.gain_dbi(90, 90), 8.0);
  EXPECT_DOUBLE_EQ(g.gain_dbi(315, 90), (16.0 + 4.0) / 2);
  EXPECT_DOUBLE_EQ(g.gain_dbi(315, 0), (16.0 + 4.0) / 4);
  EXPECT_DOUBLE_EQ(g.gain_dbi(45, -45), (4.0 + 8.0) / 2 / 4);
}

TEST(AntennaPatternFile, TheStageRefusesABrokenFileWithItsPathAndLine) {
  const auto dir = std::filesystem::temp_directory_path() / "rfsitl_antenna_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "broken.csv") << "el,0,360\n-90,1,1\n0,1,x\n90,1,1\n";
  const std::string path = (dir / "broken.csv").string();
  try {
    make_stage(settings("file", "down", 0.0, "broken.csv"), dir.string());
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":3: ", 0), 0u) << e.what();
  }
  try {
    make_stage(settings("file", "down", 0.0, "absent.csv"), dir.string());
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("absent.csv"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

/// The key of the SettingError validate() throws for `s`, or "(accepted)".
std::string refused_key(const config::Settings& s) {
  try {
    find_channel_stage("antenna")->info.validate(s);
  } catch (const config::SettingError& e) {
    return e.key();
  }
  return "(accepted)";
}

TEST(AntennaPatternFile, SettingsNeedAFileExactlyWithPatternFile) {
  EXPECT_EQ(refused_key(settings("file")), "file");
  EXPECT_EQ(refused_key(settings("patch", "down", 0.0, kPatchFile)), "file");
  EXPECT_EQ(refused_key(settings("file", "down", 3.0, kPatchFile)), "gain_dbi");
  EXPECT_EQ(refused_key(settings("file", "down", 0.0, kPatchFile)), "(accepted)");
}

}  // namespace
}  // namespace rfsitl::channel
