// Trace replay: CSV samples and ns-2 setdest files replayed exactly, and every
// bad line skipped and reported with its line number.
#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>
#include <string>

#include "mobility_test_support.hpp"
#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "rfsitl/position/mobility/ns2_trace.hpp"
#include "rfsitl/position/mobility/trace_replay_model.hpp"
#include "temp_dir.hpp"

namespace rfsitl::position::mobility {
namespace {

using testing::near;
using testing::velocity_is_derivative;
const GeodeticPosition kOrigin{43.0008, -78.789, 180.0};

std::string errors_of(const TraceParseResult& r) {
  std::string out;
  for (const auto& e : r.errors) out += r.message(e) + "\n";
  return out;
}

TraceReplayModel replay(const TraceParseResult& r, std::uint32_t node) {
  return TraceReplayModel(r.tracks.at(node));
}

TEST(MobilityCsvTrace, LocalSamplesReplayExactlyPerNode) {
  const auto r = parse_csv_trace(
      "t,node,x,y,z\n"
      "0, 1, 0, 0, 10\n"
      "0, 2, 500, 500, 30\n"
      "10, 1, 100, 0, 10\n"
      "# a comment, then a blank line\n"
      "\n"
      "20, 1, 100, 200, 50\r\n"
      "5, 2, 500, 450, 30\n",
      "flight.csv", {});
  EXPECT_EQ(r.bad_lines, 0u) << errors_of(r);
  ASSERT_EQ(r.tracks.size(), 2u);
  TraceReplayModel one = replay(r, 1);
  EXPECT_TRUE(near(one.state_at(0).position, {0, 0, 10}, 0.0));
  EXPECT_TRUE(near(one.state_at(10).position, {100, 0, 10}, 0.0));
  EXPECT_TRUE(near(one.state_at(20).position, {100, 200, 50}, 0.0));
  EXPECT_TRUE(near(one.state_at(4).position, {40, 0, 10}));
  EXPECT_TRUE(near(one.state_at(4).velocity, {10, 0, 0}));
  EXPECT_TRUE(near(one.state_at(15).velocity, {0, 20, 4}));
  EXPECT_TRUE(near(one.state_at(99).position, {100, 200, 50}, 0.0));  // the last holds
  EXPECT_TRUE(near(one.state_at(99).velocity, {0, 0, 0}, 0.0));
  EXPECT_TRUE(velocity_is_derivative(one, 12.34));
  TraceReplayModel two = replay(r, 2);
  EXPECT_TRUE(near(two.state_at(2.5).position, {500, 475, 30}));
}

TEST(MobilityCsvTrace, TheFirstSampleHoldsBeforeItsTime) {
  const auto r = parse_csv_trace("30,4,1,2,3\n40,4,11,2,3\n", "late.csv", {});
  TraceReplayModel m = replay(r, 4);
  EXPECT_TRUE(near(m.state_at(0).position, {1, 2, 3}, 0.0));
  EXPECT_TRUE(near(m.state_at(0).velocity, {0, 0, 0}, 0.0));
  EXPECT_TRUE(near(m.state_at(35).position, {6, 2, 3}));
}

TEST(MobilityCsvTrace, Wgs84SamplesByHeaderOrByOption) {
  const std::string rows = "0,3,43.0008,-78.789,200\n60,3,43.0018,-78.789,200\n";
  const auto by_header = parse_csv_trace(" T , Node , LAT , lon , alt\n" + rows, "g.csv",
                                         {kOrigin, CsvCoordinates::kLocal});
  const auto by_option = parse_csv_trace(rows, "g.csv", {kOrigin, CsvCoordinates::kGeodetic});
  for (const auto* r : {&by_header, &by_option}) {
    EXPECT_EQ(r->bad_lines, 0u) << errors_of(*r);
    TraceReplayModel m = replay(*r, 3);
    const LocalPosition a = to_local(GeodeticPosition{43.0008, -78.789, 200}, kOrigin);
    const LocalPosition b = to_local(GeodeticPosition{43.0018, -78.789, 200}, kOrigin);
    EXPECT_TRUE(near(m.state_at(0).position, a, 1e-9));
    EXPECT_TRUE(near(m.state_at(60).position, b, 1e-9));
    EXPECT_NEAR(m.state_at(30).velocity.vy_mps, 111.1 / 60, 0.01);  // 1e-3 deg north in 60 s
  }
  // The same numbers read as metres are another place entirely.
  const auto as_metres = parse_csv_trace(rows, "g.csv", {kOrigin, CsvCoordinates::kLocal});
  EXPECT_TRUE(near(replay(as_metres, 3).state_at(0).position, {43.0008, -78.789, 200}, 0.0));
}

TEST(MobilityCsvTrace, BadLinesAreSkippedCountedAndNamedByLine) {
  const auto r = parse_csv_trace(
      "t,node,x,y,z\n"    // 1
      "0,1,0,0,0\n"       // 2
      "1,1,10,0\n"        // 3: four fields
      "2,1,abc,0,0\n"     // 4
      "3,70000,0,0,0\n"   // 5
      "4,1,0,0,200000\n"  // 6: z above the altitude limit
      "-1,1,0,0,0\n"      // 7
      "10,1,100,0,0\n"    // 8
      "9,1,90,0,0\n"      // 9: earlier than line 8 for node 1
      "nan,1,0,0,0\n"     // 10
      "11,1,1e9,0,0\n",   // 11: beyond the local frame's bound
      "bad.csv", {});
  EXPECT_EQ(r.bad_lines, 8u);
  EXPECT_EQ(errors_of(r),
            "bad.csv:3: expected 5 comma-separated fields (t, node, x, y, z), got 4\n"
            "bad.csv:4: x 'abc' is not a finite number\n"
            "bad.csv:5: node '70000' is not an integer in 0..65535\n"
            "bad.csv:6: z 200000 out of range [-1000, 100000]\n"
            "bad.csv:7: t -1 out of range [0, 1000000000000]\n"
            "bad.csv:9: t 9 is before node 1's previous sample at t 10\n"
            "bad.csv:10: t 'nan' is not a finite number\n"
            "bad.csv:11: x 1000000000 out of range [-10000000, 10000000]\n");
  // The good samples still make the track: the last good position stays in force.
  TraceReplayModel m = replay(r, 1);
  EXPECT_TRUE(near(m.state_at(5).position, {50, 0, 0}));
  EXPECT_TRUE(near(m.state_at(1000).position, {100, 0, 0}, 0.0));
}

TEST(MobilityCsvTrace, AnUnknownHeaderStopsTheFileWithOneError) {
  const auto r = parse_csv_trace("\n# made by hand\nt,id,e,n,u\n0,1,0,0,0\n", "h.csv", {});
  EXPECT_EQ(r.bad_lines, 1u);
  EXPECT_TRUE(r.tracks.empty());
  EXPECT_EQ(errors_of(r),
            "h.csv:3: unknown header: expected t,node,x,y,z or t,node,lat,lon,alt; the rest of "
            "the file is not read\n");
}

TEST(MobilityCsvTrace, KeepsTheFirstHundredReasonsButCountsEveryBadLine) {
  std::string text;
  for (int i = 0; i < 250; ++i) text += "junk\n";
  const auto r = parse_csv_trace(text, "junk.csv", {});
  EXPECT_EQ(r.bad_lines, 250u);
  ASSERT_EQ(r.errors.size(), TraceParseResult::kMaxReportedErrors);
  EXPECT_EQ(r.errors.back().line, 100u);
}

TEST(MobilityCsvTrace, ReadsFilesAndNamesOneItCannotRead) {
  rfsitl::testing::TempDir dir("mobility-csv");
  const std::string path = dir.path("trace.csv");
  std::ofstream(path) << "0,1,5,5,5\nbroken\n";
  const auto r = read_csv_trace(path, {});
  EXPECT_EQ(r.source, path);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_EQ(r.message(r.errors[0]), path +
                                        ":2: expected 5 comma-separated fields (t, node, x, "
                                        "y, z), got 1");
  EXPECT_THROW(read_csv_trace(dir.path("missing.csv"), {}), std::runtime_error);
}

// A file as setdest / BonnMotion write it, with a teleport and an interruption.
constexpr const char* kNs2 =
    "# nodes: 2, max time: 100\n"
    "$node_(0) set X_ 10.0\n"
    "$node_(0) set Y_ 20.0\n"
    "$node_(0) set Z_ 0.0\n"
    "$node_(1) set X_ 0.0\n"
    "$node_(1) set Y_ 0.0\n"
    "$god_ set-dist 0 1 1\n"
    "$ns_ at 2.0 \"$node_(0) setdest 40.0 60.0 5.0\"\n"  // 50 m at 5 m/s: arrives at 12
    "$ns_ at 20.0 \"$node_(0) setdest 40.0 0.0 2.0\"\n"  // 60 m at 2 m/s: would arrive at 50
    "$ns_ at 30.0 \"$node_(0) setdest 0.0 40.0 4.0\"\n"  // interrupts at (40, 40)
    "$ns_ at 1.0 \"$god_ set-dist 0 1 2\"\n"
    "$ns_ at 5.0 \"$node_(1) setdest 30.0 40.0 10.0\"\n"  // arrives at 10
    "$ns_ at 15.0 \"$node_(1) set X_ 100.0\"\n"           // a jump
    "$node_(1) set Z_ 25.0\n";                            // initial, though late in the file

TEST(MobilityNs2Trace, SetdestIsReplayedExactly) {
  const auto r = parse_ns2_trace(kNs2, "scen.ns_movements");
  EXPECT_EQ(r.bad_lines, 0u) << errors_of(r);
  ASSERT_EQ(r.tracks.size(), 2u);
  TraceReplayModel a = replay(r, 0);
  EXPECT_TRUE(near(a.state_at(0).position, {10, 20, 0}, 0.0));
  EXPECT_TRUE(near(a.state_at(2).position, {10, 20, 0}, 0.0));
  EXPECT_TRUE(near(a.state_at(2).velocity, {3, 4, 0}));
  EXPECT_TRUE(near(a.state_at(7).position, {25, 40, 0}));
  EXPECT_TRUE(near(a.state_at(12).position, {40, 60, 0}));  // stops at the destination
  EXPECT_TRUE(near(a.state_at(16).position, {40, 60, 0}));
  EXPECT_TRUE(near(a.state_at(16).velocity, {0, 0, 0}, 0.0));
  EXPECT_TRUE(near(a.state_at(25).position, {40, 50, 0}));
  EXPECT_TRUE(near(a.state_at(25).velocity, {0, -2, 0}));
  EXPECT_TRUE(near(a.state_at(30).position, {40, 40, 0}));  // the interrupted leg's point
  EXPECT_TRUE(near(a.state_at(30).velocity, {-4, 0, 0}));
  EXPECT_TRUE(near(a.state_at(40).position, {0, 40, 0}));
  EXPECT_TRUE(near(a.state_at(500).position, {0, 40, 0}));
  for (double t = 2.5; t < 40; t += 1.3) EXPECT_TRUE(velocity_is_derivative(a, t));

  TraceReplayModel b = replay(r, 1);
  EXPECT_TRUE(near(b.state_at(0).position, {0, 0, 25}, 0.0));
  EXPECT_TRUE(near(b.state_at(7.5).position, {15, 20, 25}));
  EXPECT_TRUE(near(b.state_at(7.5).velocity, {6, 8, 0}));
  EXPECT_TRUE(near(b.state_at(14.999).position, {30, 40, 25}));
  EXPECT_TRUE(near(b.state_at(15).position, {100, 40, 25}, 0.0));  // jumped at 15
  EXPECT_TRUE(near(b.state_at(60).position, {100, 40, 25}, 0.0));
}

TEST(MobilityNs2Trace, SpeedZeroOrTheSamePointStopsTheNode) {
  const auto r = parse_ns2_trace(
      "$node_(2) set X_ 5\n"
      "$ns_ at 0.0 \"$node_(2) setdest 5 0 0.00\"\n"
      "$ns_ at 1.0 \"$node_(2) setdest 105 0 10\"\n"
      "$ns_ at 6.0 \"$node_(2) setdest 0 0 0\"\n",
      "s.tcl");
  EXPECT_EQ(r.bad_lines, 0u) << errors_of(r);
  TraceReplayModel m = replay(r, 2);
  EXPECT_TRUE(near(m.state_at(0.5).position, {5, 0, 0}, 0.0));
  EXPECT_TRUE(near(m.state_at(3).position, {25, 0, 0}));
  EXPECT_TRUE(near(m.state_at(6).position, {55, 0, 0}));  // speed 0: stops where it is
  EXPECT_TRUE(near(m.state_at(100).position, {55, 0, 0}));
}

TEST(MobilityNs2Trace, BadLinesAreSkippedCountedAndNamedByLine) {
  const auto r = parse_ns2_trace(
      "$node_(0) set X_ 1\n"                          // 1
      "$node_(x) set X_ 1\n"                          // 2
      "$node_(0) set W_ 1\n"                          // 3
      "$node_(0) set Y_\n"                            // 4
      "$ns_ at -2 \"$node_(0) setdest 1 2 3\"\n"      // 5
      "$ns_ at 2 $node_(0) setdest 1 2 3\n"           // 6: not quoted
      "$ns_ at 3 \"$node_(0) setdest 1 2 -3\"\n"      // 7
      "$ns_ at 4 \"$node_(0) setdest 1 2e9 3\"\n"     // 8
      "$ns_ at 5 \"$node_(0) fly 1 2 3\"\n"           // 9
      "set opt(x) 670\n"                              // 10
      "$ns_ at 6 \"$node_(0) setdest 1 2 1e-300\"\n"  // 11
      "$ns_ at 7 \"$node_(0) setdest 100 0 10\"\n",   // 12: good
      "bad.tcl");
  EXPECT_EQ(r.bad_lines, 10u);
  EXPECT_EQ(errors_of(r),
            "bad.tcl:2: node '$node_(x)' is not $node_(i) with i in 0..65535\n"
            "bad.tcl:3: unknown variable 'W_': expected X_, Y_ or Z_\n"
            "bad.tcl:4: expected $node_(i) set X_|Y_|Z_ <metres>\n"
            "bad.tcl:5: t -2 out of range [0, 1000000000000]\n"
            "bad.tcl:6: the command after $ns_ at <time> must be in double quotes\n"
            "bad.tcl:7: speed '-3' is not a number >= 0\n"
            "bad.tcl:8: y 2000000000 out of range [-10000000, 10000000]\n"
            "bad.tcl:9: expected \"$node_(i) setdest <x> <y> <speed>\" or \"$node_(i) set X_ "
            "<metres>\"\n"
            "bad.tcl:10: unknown statement 'set': expected $node_(i) set, $ns_ at, or $god_\n"
            "bad.tcl:11: speed 1e-300 is too small for a leg to end\n");
  TraceReplayModel m = replay(r, 0);
  EXPECT_TRUE(near(m.state_at(7).position, {1, 0, 0}, 0.0));
  EXPECT_TRUE(near(m.state_at(8).position, {11, 0, 0}));
}

}  // namespace
}  // namespace rfsitl::position::mobility
