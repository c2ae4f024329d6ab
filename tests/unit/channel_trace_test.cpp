// The trace stage against its documented model (docs/channel_traces.md): the
// gain 10^(G/20) exp(j P pi/180) with G and the unwrapped P interpolated
// linearly, written out here per case; the ends, looping, missing links and
// reciprocal fill-in; the NPY layout (files built in memory); and every kind of
// broken file refused with its line or byte named.
#include "rfsitl/channel/stages/trace.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "rfsitl/config/settings.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::channel {
namespace {

using Complex = std::complex<double>;

/// The model's gain for G dB and P degrees, written out.
Complex expected(double gain_db, double phase_deg) {
  const double amplitude = std::pow(10.0, gain_db / 20.0);
  const double rad = phase_deg * std::numbers::pi / 180.0;
  return {amplitude * std::cos(rad), amplitude * std::sin(rad)};
}

void expect_gain(const Complex& got, const Complex& want) {
  EXPECT_NEAR(got.real(), want.real(), 1e-12 * (1.0 + std::abs(want))) << got << " vs " << want;
  EXPECT_NEAR(got.imag(), want.imag(), 1e-12 * (1.0 + std::abs(want))) << got << " vs " << want;
}

LinkGeometry link(std::size_t tx, std::size_t rx, double t_s) {
  LinkGeometry g;
  g.tx.index = tx;
  g.rx.index = rx;
  g.time_s = t_s;
  return g;
}

/// A stage from CSV text for nodes whose ids are `ids` (index i has id ids[i]).
std::unique_ptr<GainStage> stage_of(const std::string& csv, const std::vector<NodeId>& ids,
                                    TraceSettings s = {}) {
  return trace::make_stage(s, trace::parse_csv(csv, "trace.csv", ids), ids);
}

const std::vector<NodeId> kIds{7, 3, 12};  // indices 0, 1, 2

TEST(ChannelTrace, InterpolatesDbAndUnwrappedPhaseAtAndBetweenSamples) {
  // 3 -> 12 is index 1 -> 2. Phases 170, -170, 0 unwrap to 170, 190, 360.
  const auto stage = stage_of(
      "t_s,tx,rx,gain_db,phase_deg\n"
      "0,3,12,-10,170\n"
      "1,3,12,-20,-170\n"
      "3,3,12,-20,0\n",
      kIds);
  EXPECT_TRUE(stage->time_varying());
  expect_gain(stage->gain(link(1, 2, 0.0)), expected(-10, 170));
  expect_gain(stage->gain(link(1, 2, 1.0)), expected(-20, 190));
  expect_gain(stage->gain(link(1, 2, 3.0)), expected(-20, 360));
  // Halfway through the wrap: 180 degrees, not 0 (the long way round).
  expect_gain(stage->gain(link(1, 2, 0.5)), expected(-15, 180));
  expect_gain(stage->gain(link(1, 2, 0.25)), expected(-12.5, 175));
  expect_gain(stage->gain(link(1, 2, 2.0)), expected(-20, 190 + 0.5 * (360 - 190)));
}

TEST(ChannelTrace, HoldsTheEndValuesOutsideTheTrace) {
  const auto stage = stage_of("t_s,tx,rx,gain_db,phase_deg\n2,7,3,-4,30\n5,7,3,-8,60\n", kIds);
  expect_gain(stage->gain(link(0, 1, 0.0)), expected(-4, 30));
  expect_gain(stage->gain(link(0, 1, 1.999)), expected(-4, 30));
  expect_gain(stage->gain(link(0, 1, 5.0)), expected(-8, 60));
  expect_gain(stage->gain(link(0, 1, 1e6)), expected(-8, 60));
}

TEST(ChannelTrace, EqualTimesAreAStepTheLaterRowHolding) {
  const auto stage = stage_of(
      "t_s,tx,rx,gain_db,phase_deg\n0,7,3,0,0\n1,7,3,-10,0\n1,7,3,-30,0\n2,7,3,-30,0\n", kIds);
  expect_gain(stage->gain(link(0, 1, 0.5)), expected(-5, 0));
  expect_gain(stage->gain(link(0, 1, 1.0)), expected(-30, 0));
}

TEST(ChannelTrace, LoopRepeatsTheWholeFileWithItsPeriod) {
  // The file spans [1, 3] (period 2); 3->7 ends at 2 and holds until 3.
  const std::string csv =
      "t_s,tx,rx,gain_db,phase_deg\n"
      "1,7,3,0,0\n3,7,3,-20,90\n"
      "1,3,7,-6,0\n2,3,7,-12,0\n";
  TraceSettings s;
  s.loop = true;
  const auto looped = stage_of(csv, kIds, s);
  expect_gain(looped->gain(link(0, 1, 4.5)), expected(-15, 67.5));  // as t = 2.5
  expect_gain(looped->gain(link(0, 1, 7.0)), expected(0, 0));       // as t = 1
  expect_gain(looped->gain(link(1, 0, 5.5)), expected(-9, 0));      // as t = 1.5
  expect_gain(looped->gain(link(1, 0, 6.5)), expected(-12, 0));     // as t = 2.5
  expect_gain(looped->gain(link(0, 1, 0.5)), expected(0, 0));       // before: the first value
  const auto once = stage_of(csv, kIds);
  expect_gain(once->gain(link(0, 1, 4.5)), expected(-20, 90));
}

TEST(ChannelTrace, MissingLinksAreUnityOrBlockedAndTheDiagonalIsOne) {
  const std::string csv = "t_s,tx,rx,gain_db,phase_deg\n0,7,3,-10,45\n";
  TraceSettings block;
  block.missing = TraceMissing::kBlock;
  const auto unity = stage_of(csv, kIds);
  const auto blocked = stage_of(csv, kIds, block);
  for (const auto& [tx, rx] : {std::pair<std::size_t, std::size_t>{0, 2}, {2, 1}, {2, 0}}) {
    expect_gain(unity->gain(link(tx, rx, 1.0)), 1.0);
    expect_gain(blocked->gain(link(tx, rx, 1.0)), 0.0);
  }
  expect_gain(blocked->gain(link(2, 2, 1.0)), 1.0);
  expect_gain(blocked->gain(link(0, 1, 1.0)), expected(-10, 45));
}

TEST(ChannelTrace, ReciprocalFillsOnlyTheDirectionsTheFileLacks) {
  const std::string one_way = "t_s,tx,rx,gain_db,phase_deg\n0,7,3,-10,45\n";
  const auto filled = stage_of(one_way, kIds);
  expect_gain(filled->gain(link(1, 0, 0.0)), expected(-10, 45));
  EXPECT_TRUE(filled->reciprocal());

  TraceSettings off;
  off.reciprocal = false;
  off.missing = TraceMissing::kBlock;
  const auto not_filled = stage_of(one_way, kIds, off);
  expect_gain(not_filled->gain(link(1, 0, 0.0)), 0.0);
  EXPECT_FALSE(not_filled->reciprocal());

  const auto both = stage_of(one_way + "0,3,7,-20,-90\n", kIds);
  expect_gain(both->gain(link(0, 1, 0.0)), expected(-10, 45));
  expect_gain(both->gain(link(1, 0, 0.0)), expected(-20, -90));
  EXPECT_FALSE(both->reciprocal());
}

TEST(ChannelTrace, UpdateIntervalIsTheGridOfTheSettings) {
  TraceSettings s;
  s.update_rate_hz = 250.0;
  EXPECT_DOUBLE_EQ(
      stage_of("t_s,tx,rx,gain_db,phase_deg\n0,7,3,0,0\n", kIds, s)->update_interval_s(),
      1.0 / 250.0);
}

TEST(ChannelTrace, CsvAcceptsCommentsBlankLinesSpacesAndCrLf) {
  const trace::Trace t = trace::parse_csv(
      "# measured\r\n\r\n t_s , tx , rx , gain_db , phase_deg\r\n0.5, 7, 3, -1.5e1, 2\r\n", "x.csv",
      kIds);
  ASSERT_EQ(t.links.size(), 1u);
  EXPECT_EQ(t.links[0].link, (trace::LinkIds{7, 3}));
  ASSERT_EQ(t.links[0].samples.size(), 1u);
  EXPECT_EQ(t.links[0].samples[0].t_s, 0.5);
  EXPECT_EQ(t.links[0].samples[0].gain_db, -15.0);
  EXPECT_EQ(t.links[0].samples[0].phase_deg, 2.0);
}

/// The message of the std::invalid_argument `f` throws ("" if none).
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ChannelTrace, RefusesBrokenCsvNamingFileAndLine) {
  const std::string h = "t_s,tx,rx,gain_db,phase_deg\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"", "trace.csv:1: no header line"},
      {"# nothing\n", "trace.csv:1: no header line"},
      {h, "trace.csv:1: no samples"},
      {"t,tx,rx,gain_db,phase_deg\n0,7,3,0,0\n", "trace.csv:1: the first line must be the header"},
      {h + "0,7,3,0\n", "trace.csv:2: expected 5 fields"},
      {h + "0,7,3,0,0,1\n", "trace.csv:2: expected 5 fields"},
      {h + "zero,7,3,0,0\n", "trace.csv:2: t_s 'zero' is not a finite number"},
      {h + "0,7,3,-3dB,0\n", "trace.csv:2: gain_db '-3dB' is not a finite number"},
      {h + "0,7,3,0,nan\n", "trace.csv:2: phase_deg 'nan' is not a finite number"},
      {h + "0,7,3,inf,0\n", "trace.csv:2: gain_db 'inf' is not a finite number"},
      {h + "0,7,9,0,0\n", "trace.csv:2: rx: unknown node id 9"},
      {h + "0,300,3,0,0\n", "trace.csv:2: tx: unknown node id 300"},
      {h + "0,x,3,0,0\n", "trace.csv:2: tx: 'x' is not a node id"},
      {h + "0,7,7,0,0\n", "trace.csv:2: tx and rx are the same node (id 7)"},
      {h + "-1,7,3,0,0\n", "trace.csv:2: t_s -1 is outside [0, 1e9]"},
      {h + "0,7,3,101,0\n", "trace.csv:2: gain_db 101 is outside [-300, 100]"},
      {h + "0,7,3,0,2e9\n", "trace.csv:2: phase_deg 2e+09 is outside [-1e9, 1e9]"},
      {"t_s,tx,rx,gain_db,phase_deg\n0.7,3,12,0,0\n0,7,3,0,0\n\n# c\n0.5,3,12,0,0\n",
       "trace.csv:6: t_s goes backwards for link 3->12 (0.5 after 0.7)"},
  };
  for (const auto& [text, message] : cases) {
    const std::string what = refusal([&] { trace::parse_csv(text, "trace.csv", kIds); });
    EXPECT_EQ(what.rfind(message, 0), 0u) << "text:\n" << text << "message: " << what;
  }
}

TEST(ChannelTrace, RefusesBrokenLinksFileNamingFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"", "links.csv:1: no header line 'tx,rx'"},
      {"rx,tx\n7,3\n", "links.csv:1: the first line must be the header 'tx,rx'"},
      {"tx,rx\n", "links.csv:1: no links"},
      {"tx,rx\n7,3\n3,7\n7,3\n", "links.csv:4: link 7->3 is listed twice (first on line 2)"},
      {"tx,rx\n7,3,1\n", "links.csv:2: expected 2 fields"},
      {"tx,rx\n7,4\n", "links.csv:2: rx: unknown node id 4"},
  };
  for (const auto& [text, message] : cases) {
    const std::string what = refusal([&] { trace::parse_links_csv(text, "links.csv", kIds); });
    EXPECT_EQ(what.rfind(message, 0), 0u) << "text:\n" << text << "message: " << what;
  }
}

/// An NPY file as numpy.save writes it: magic, version, header length (LE),
/// the dict padded with spaces to a multiple of 64 and '\n', then `values` LE.
std::vector<std::uint8_t> npy(const std::string& dict, const std::vector<double>& values,
                              bool f4 = false, unsigned major = 1) {
  const std::size_t preamble = major == 1 ? 10 : 12;
  std::string header = dict;
  while ((preamble + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::vector<std::uint8_t> out{0x93, 'N', 'U', 'M', 'P', 'Y', static_cast<std::uint8_t>(major), 0};
  for (std::size_t i = 0; i < preamble - 8; ++i) {
    out.push_back(static_cast<std::uint8_t>(header.size() >> (8 * i)));
  }
  out.insert(out.end(), header.begin(), header.end());
  for (const double v : values) {
    const std::uint64_t bits =
        f4 ? std::bit_cast<std::uint32_t>(static_cast<float>(v)) : std::bit_cast<std::uint64_t>(v);
    for (std::size_t i = 0; i < (f4 ? 4u : 8u); ++i) {
      out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
    }
  }
  return out;
}

std::string dict(const std::string& descr, const std::string& shape) {
  return "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
}

const std::vector<trace::LinkIds> kNpyLinks{{7, 3}, {3, 12}};
// (T = 3, L = 2, 2): row k = [link 0 (g, p), link 1 (g, p)], exact in float32.
const std::vector<double> kNpyValues{-10, 0,  -40,   90,   //
                                     -20, 10, -41,   100,  //
                                     -30, 20, -42.5, 110};

TEST(ChannelTrace, ReadsNpyRowsLinksAndFieldsInTheirLayout) {
  for (const bool f4 : {false, true}) {
    for (const unsigned major : {1u, 2u}) {
      const auto bytes = npy(dict(f4 ? "<f4" : "<f8", "(3, 2, 2)"), kNpyValues, f4, major);
      const trace::Trace t = trace::parse_npy(bytes, "t.npy", kNpyLinks, 0.5);
      ASSERT_EQ(t.links.size(), 2u);
      const auto stage = trace::make_stage({}, t, kIds);
      // Row k is at t = 0.5 k; link 1 (3->12) is index 1 -> 2.
      expect_gain(stage->gain(link(0, 1, 0.5)), expected(-20, 10));
      expect_gain(stage->gain(link(1, 2, 1.0)), expected(-42.5, 110));
      expect_gain(stage->gain(link(1, 2, 0.25)), expected(-40.5, 95));
      expect_gain(stage->gain(link(0, 1, 0.75)), expected(-25, 15));
    }
  }
}

TEST(ChannelTrace, RefusesBrokenNpyNamingByteAndField) {
  const auto good = npy(dict("<f8", "(3, 2, 2)"), kNpyValues);
  auto with = [&](std::size_t at, std::uint8_t b) {
    auto v = good;
    v[at] = b;
    return v;
  };
  auto cut = [&](std::size_t n) {
    return std::vector<std::uint8_t>(good.begin(), good.begin() + n);
  };
  auto nan_at = [&](std::size_t value) {  // value index in kNpyValues
    auto v = kNpyValues;
    v[value] = std::nan("");
    return npy(dict("<f8", "(3, 2, 2)"), v);
  };
  // Where npy() put the data (the header padded to 64 bytes), and its header length.
  const std::size_t data = good.size() - kNpyValues.size() * 8;
  const std::size_t header_len = data - 10;
  ASSERT_EQ(data % 64, 0u);
  const std::vector<std::pair<std::vector<std::uint8_t>, std::string>> cases{
      {with(0, 'X'), "t.npy: byte 0 (magic): not an NPY file"},
      {cut(7), "t.npy: byte 7 (version)"},
      {with(6, 3), "t.npy: byte 6 (version): NPY format 3.0 is not supported"},
      {with(7, 1), "t.npy: byte 6 (version): NPY format 1.1 is not supported"},
      {cut(9), "t.npy: byte 8 (header length)"},
      {with(9, 0x10), "t.npy: byte 8 (header length): " + std::to_string(header_len + 0x1000) +
                          " bytes of header run past the end"},
      {with(10, '['), "t.npy: byte 10 (header): expected '{', found '['"},
      {npy(dict("<i4", "(3, 2, 2)"), kNpyValues),
       "t.npy: byte 20 (header field 'descr'): '<i4' is not supported"},
      {npy(dict(">f8", "(3, 2, 2)"), kNpyValues), "t.npy: byte 20 (header field 'descr')"},
      {npy("{'descr': '<f8', 'fortran_order': True, 'shape': (3, 2, 2), }", kNpyValues),
       "t.npy: byte 44 (header field 'fortran_order'): must be False"},
      {npy("{'descr': '<f8', 'fortran_order': Nope, 'shape': (3, 2, 2), }", kNpyValues),
       "t.npy: byte 44 (header field 'fortran_order'): expected True or False"},
      {npy(dict("<f8", "(3, 3, 2)"), kNpyValues),
       "t.npy: byte 60 (header field 'shape'): (3, 3, 2) is not (T, L, 2)"},
      {npy(dict("<f8", "(12,)"), kNpyValues), "t.npy: byte 60 (header field 'shape'): (12,) is"},
      {npy(dict("<f8", "(3, 2, x)"), kNpyValues),
       "t.npy: byte 67 (header field 'shape'): expected a dimension"},
      {npy("{'descr': '<f8', 'shape': (3, 2, 2), }", kNpyValues),
       "t.npy: byte 64 (header): field 'fortran_order' is missing"},
      {npy("{'descr': '<f8', 'descr': '<f8', }", kNpyValues),
       "t.npy: byte 27 (header): field 'descr' appears twice"},
      {npy(dict("<f8", "(3, 2, 2)") + "x", kNpyValues), "t.npy: byte 72 (header): text after"},
      {npy("{'descr': '<f8', 'colour': 1}", kNpyValues),
       "t.npy: byte 27 (header): unknown field 'colour'"},
      {npy(dict("<f8", "(4, 2, 2)"), kNpyValues),
       "t.npy: byte " + std::to_string(data) +
           " (data): shape (4, 2, 2) of <f8 needs 128 bytes of data, the file has 96"},
      {cut(good.size() - 1), "t.npy: byte " + std::to_string(data) + " (data)"},
      {nan_at(6), "t.npy: byte " + std::to_string(data + 6 * 8) + " (row 1, link 3->12, gain_db)"},
      {nan_at(7),
       "t.npy: byte " + std::to_string(data + 7 * 8) + " (row 1, link 3->12, phase_deg)"},
  };
  for (const auto& [bytes, message] : cases) {
    const std::string what = refusal([&] { trace::parse_npy(bytes, "t.npy", kNpyLinks, 0.5); });
    EXPECT_EQ(what.rfind(message, 0), 0u) << "want: " << message << "\ngot:  " << what;
  }
}

TEST(ChannelTrace, RefusesAFileOver256MiBBeforeReadingIt) {
  const auto dir = std::filesystem::temp_directory_path() / "rfsitl_channel_trace_test";
  std::filesystem::create_directories(dir);
  const auto big = dir / "big.csv";
  { std::ofstream(big) << "t_s,tx,rx,gain_db,phase_deg\n"; }
  std::filesystem::resize_file(big, trace::kMaxFileBytes + 1);  // sparse: no disk used
  TraceSettings s;
  s.file = "big.csv";
  const std::string what = refusal([&] { trace::load(s, dir.string(), kIds); });
  EXPECT_NE(what.find("big.csv: 268435457 bytes, more than the 256 MiB"), std::string::npos)
      << what;
  std::filesystem::remove_all(dir);
}

TEST(ChannelTrace, SettingsRulesNameTheKey) {
  const ChannelStageComponent* c = find_channel_stage("trace");
  ASSERT_NE(c, nullptr);
  auto key_refused = [&](const std::vector<std::pair<std::string, config::Value>>& values) {
    config::Settings s = c->info.defaults();
    for (const auto& [k, v] : values) s.set(k, v);
    try {
      c->info.validate(s);
    } catch (const config::SettingError& e) {
      return e.key();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(key_refused({}), "file");
  EXPECT_EQ(key_refused({{"file", std::string("t.txt")}}), "file");
  EXPECT_EQ(key_refused({{"file", std::string("t.npy")}, {"step_s", 0.01}}), "links_file");
  EXPECT_EQ(key_refused({{"file", std::string("t.NPY")}, {"links_file", std::string("l.csv")}}),
            "step_s");
  EXPECT_EQ(key_refused({{"file", std::string("t.csv")}, {"step_s", 0.01}}), "step_s");
  EXPECT_EQ(key_refused({{"file", std::string("t.csv")}}), "(accepted)");
}

/// The component's make() on the example, its nodes named by the context.
void expect_component_replays(StageContext context, const std::string& dir, const std::string& file,
                              const trace::Sample& first) {
  context.node_ids = {1, 2};
  context.source_dir = dir;
  config::Settings settings = find_channel_stage("trace")->info.defaults();
  settings.set("file", file);
  const auto stage = find_channel_stage("trace")->make(settings, context);
  expect_gain(stage->gain(link(0, 1, 0.0)), expected(first.gain_db, first.phase_deg));
  expect_gain(stage->gain(link(1, 0, 0.0)), expected(first.gain_db, first.phase_deg));
}

TEST(ChannelTrace, TheExampleTraceLoadsAndTheComponentBuildsIt) {
  const std::string dir = std::string(RFSITL_SOURCE_DIR) + "/scenarios";
  TraceSettings s;
  s.file = "traces/two_node_walk.csv";
  const trace::Trace t = trace::load(s, dir, std::vector<NodeId>{1, 2});
  ASSERT_EQ(t.links.size(), 1u);
  EXPECT_EQ(t.links[0].samples.size(), 251u);
  EXPECT_EQ(t.links[0].samples.front().t_s, 0.0);
  EXPECT_EQ(t.links[0].samples.back().t_s, 10.0);
  expect_component_replays(StageContext{}, dir, s.file, t.links[0].samples.front());
}

}  // namespace
}  // namespace rfsitl::channel
