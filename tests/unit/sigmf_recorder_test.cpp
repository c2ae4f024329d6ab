#include "rfsitl/monitor/sigmf_recorder.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include "frame_event_builder.hpp"
#include "rfsitl/common/build_version.hpp"
#include "temp_dir.hpp"

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rfsitl::monitor {
namespace {

namespace fs = std::filesystem;
using engine::FrameEvent;
using engine::FrameEventKind;
using engine::LossReason;
using nlohmann::json;

constexpr std::size_t kTick = 100;

/// A temp directory for this file's tests (not created: the recorder makes it).
class TempDir : public rfsitl::testing::TempDir {
 public:
  TempDir() : rfsitl::testing::TempDir("rfsitl-sigmf-test", false) {}
};

/// Three nodes, ids 1, 2, 3 at indices 0, 1, 2; fs = 1 MHz, B = 100.
scenario::Scenario three_nodes() {
  scenario::Scenario s;
  s.name = "sigmf-test";
  s.seed = 11;
  for (NodeId id = 1; id <= 3; ++id) {
    scenario::NodeConfig n;
    n.id = id;
    s.nodes.push_back(n);
  }
  s.timing.sample_rate_hz = 1e6;
  s.timing.tick_samples = kTick;
  s.channel.noise_variance = 1e-11;  // -110 dB
  return s;
}

/// Sample at virtual index k: (k, -k/2), so positions can be checked exactly.
cf32 value_at(SampleTime k) {
  return {static_cast<float>(k), -0.5F * static_cast<float>(k)};
}

/// Drives the recorder as the engine does for node index `node`: asks
/// wants_samples() each tick and hands over the tick's samples if wanted.
void run_ticks(SigmfRecorder& r, std::size_t node, const std::vector<SampleTime>& ticks) {
  std::vector<cf32> block(kTick);
  for (const SampleTime t : ticks) {
    if (!r.wants_samples(node, t, kTick)) continue;
    for (std::size_t i = 0; i < kTick; ++i) block[i] = value_at(t + static_cast<SampleTime>(i));
    r.on_rx_samples(node, t, block);
  }
}

std::vector<SampleTime> ticks_until(SampleTime end) {
  std::vector<SampleTime> t;
  for (SampleTime k = 0; k < end; k += kTick) t.push_back(k);
  return t;
}

std::vector<cf32> read_data(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.size() % 8, 0U);
  std::vector<cf32> out(bytes.size() / 8);
  for (std::size_t i = 0; i < out.size(); ++i) {
    // cf32_le: little-endian float32 I then Q (this host is little-endian).
    float iq[2];
    std::memcpy(iq, bytes.data() + 8 * i, 8);
    out[i] = {iq[0], iq[1]};
  }
  return out;
}

json read_meta(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return json::parse(in);
}

FrameEvent ev(FrameEventKind kind, SampleTime t, NodeId src, NodeId dst, NodeId node,
              std::uint32_t serial, std::uint32_t len = 0) {
  return engine::testing::frame_event(kind, t, src, dst, node, serial, len);
}

FrameEvent with_snr(FrameEvent e, double snr) {
  e.snr_db = snr;
  return e;
}

FrameEvent lost(FrameEvent e, LossReason r) {
  e.reason = r;
  return e;
}

TEST(SigmfRecorder, RecordsTheWindowWithEveryFrameOnTheAirAnnotated) {
  TempDir dir;
  SigmfSettings s;
  s.directory = dir.path("a/b");  // created
  s.nodes = {2};
  s.start_s = 250e-6;  // mid-tick: virtual samples [250, 750)
  s.duration_s = 500e-6;
  auto rec = make_sigmf_recorder(s, three_nodes());
  EXPECT_FALSE(rec->wants_samples(0, 300, kTick));
  EXPECT_TRUE(rec->wants_samples(1, 300, kTick));  // node id 2 is index 1
  EXPECT_TRUE(rec->wants_samples(1, 200, kTick));  // the tick [200, 300) reaches into the window
  EXPECT_FALSE(rec->wants_samples(1, 100, kTick)) << "before the window: free to skip silence";
  EXPECT_FALSE(rec->wants_samples(2, 300, kTick));
  EXPECT_FALSE(rec->wants_samples(7, 300, kTick));

  using K = FrameEventKind;
  // F: on the air before the window only.
  rec->on_frame_event(ev(K::kTransmitted, 100, 1, 2, 1, 0x00000005, 100));
  // A: 1 -> 2 across the window's start, decoded by node 2. The engine reports
  // a unicast delivery before the receiver's event: both orders must work.
  rec->on_frame_event(ev(K::kHandedIn, 150, 1, 2, 1, 0));
  rec->on_frame_event(ev(K::kTransmitted, 200, 1, 2, 1, 0x00000000, 100));
  rec->on_frame_event(with_snr(ev(K::kDelivered, 300, 1, 2, 1, 0x00000000, 100), 30.0));
  rec->on_frame_event(with_snr(ev(K::kReceived, 300, 1, 2, 2, 0x00000000), 30.456));
  // E: a broadcast from 1 that node 3 decoded, node 2 did not.
  rec->on_frame_event(ev(K::kTransmitted, 300, 1, 255, 1, 0x00000001, 50));
  rec->on_frame_event(ev(K::kReceived, 400, 1, 255, 3, 0x00000001));
  rec->on_frame_event(with_snr(ev(K::kDelivered, 500, 1, 255, 1, 0x00000001, 50), 12.0));
  // B: 3 -> 2 lost to a collision.
  rec->on_frame_event(ev(K::kTransmitted, 400, 3, 2, 3, 0x02000000, 100));
  rec->on_frame_event(
      lost(with_snr(ev(K::kLost, 600, 3, 2, 3, 0x02000000, 100), 3.0), LossReason::kCollision));
  // G: 3 -> 1, which node 2 overhears; delivered to node 1.
  rec->on_frame_event(ev(K::kTransmitted, 450, 3, 1, 3, 0x02000001, 20));
  rec->on_frame_event(ev(K::kReceived, 500, 3, 1, 1, 0x02000001));
  rec->on_frame_event(ev(K::kDelivered, 500, 3, 1, 3, 0x02000001, 20));
  // C: node 2's own frame across the window's end, never settled.
  rec->on_frame_event(ev(K::kTransmitted, 600, 2, 1, 2, 0x01000000, 300));
  // D: after the window.
  rec->on_frame_event(ev(K::kTransmitted, 800, 1, 2, 1, 0x00000002, 100));

  run_ticks(*rec, 1, ticks_until(1000));
  EXPECT_FALSE(rec->wants_samples(1, 800, kTick)) << "the window has passed";
  EXPECT_EQ(rec->samples_written(2), 500U);
  EXPECT_EQ(rec->samples_written(1), 0U);
  rec->finish();
  rec->finish();  // idempotent

  const auto data = read_data(dir.path("a/b/node2.sigmf-data"));
  ASSERT_EQ(data.size(), 500U);
  EXPECT_EQ(fs::file_size(dir.path("a/b/node2.sigmf-data")), 4000U);
  for (std::size_t i = 0; i < data.size(); ++i) {
    ASSERT_EQ(data[i], value_at(250 + static_cast<SampleTime>(i))) << i;
  }
  EXPECT_FALSE(fs::exists(dir.path("a/b/node1.sigmf-data")));

  const json meta = read_meta(dir.path("a/b/node2.sigmf-meta"));
  const json& g = meta.at("global");
  EXPECT_EQ(g.at("core:datatype"), "cf32_le");
  EXPECT_EQ(g.at("core:sample_rate"), 1e6);
  EXPECT_EQ(g.at("core:version"), "1.0.0");
  EXPECT_EQ(g.at("core:num_channels"), 1);
  EXPECT_EQ(g.at("core:recorder"), std::string("rfsitl ") + build_version());
  EXPECT_NE(g.at("core:description").get<std::string>().find("node 2"), std::string::npos);
  EXPECT_EQ(g.at("core:extensions").at(0).at("name"), "rfsitl");
  EXPECT_EQ(g.at("rfsitl:node_id"), 2);
  EXPECT_EQ(g.at("rfsitl:node_index"), 1);
  EXPECT_NEAR(g.at("rfsitl:noise_db").get<double>(), -110.0, 1e-9);
  EXPECT_NEAR(g.at("rfsitl:front_end_gain_db").get<double>(), 110.0, 1e-9);
  EXPECT_EQ(g.at("rfsitl:recorded_samples"), 500);
  EXPECT_EQ(g.at("rfsitl:window_start_sample"), 250);
  EXPECT_EQ(g.at("rfsitl:window_samples"), 500);
  EXPECT_EQ(g.at("rfsitl:truncated"), false);

  ASSERT_EQ(meta.at("captures").size(), 1U);
  EXPECT_EQ(meta.at("captures")[0].at("core:sample_start"), 0);
  EXPECT_EQ(meta.at("captures")[0].at("core:global_index"), 250);

  const json& an = meta.at("annotations");
  ASSERT_EQ(an.size(), 5U) << an.dump(2);
  struct Want {
    std::uint64_t start, count;
    std::uint32_t serial;
    const char* outcome;
    const char* reason;
    bool own;
  };
  const Want want[] = {
      {0, 50, 0x00000000, "received", nullptr, false},     // A, clipped at the start
      {50, 50, 0x00000001, "delivered", nullptr, false},   // E
      {150, 100, 0x02000000, "lost", "collision", false},  // B
      {200, 20, 0x02000001, "delivered", nullptr, false},  // G
      {350, 150, 0x01000000, "pending", nullptr, true},    // C, clipped at the end
  };
  for (std::size_t i = 0; i < an.size(); ++i) {
    SCOPED_TRACE(an[i].dump());
    EXPECT_EQ(an[i].at("core:sample_start"), want[i].start);
    EXPECT_EQ(an[i].at("core:sample_count"), want[i].count);
    EXPECT_EQ(an[i].at("rfsitl:serial"), want[i].serial);
    EXPECT_EQ(an[i].at("rfsitl:outcome"), want[i].outcome);
    EXPECT_EQ(an[i].contains("rfsitl:reason"), want[i].reason != nullptr);
    if (want[i].reason) {
      EXPECT_EQ(an[i].at("rfsitl:reason"), want[i].reason);
    }
    EXPECT_EQ(an[i].at("rfsitl:own"), want[i].own);
    EXPECT_TRUE(an[i].contains("core:label"));
  }
  EXPECT_EQ(an[0].at("rfsitl:src"), 1);
  EXPECT_EQ(an[0].at("rfsitl:dst"), 2);
  EXPECT_EQ(an[0].at("rfsitl:final_outcome"), "delivered");
  EXPECT_NEAR(an[0].at("rfsitl:snr_db").get<double>(), 30.46, 1e-9);  // at this receiver
  EXPECT_EQ(an[0].at("rfsitl:frame_start"), 200);
  EXPECT_EQ(an[0].at("rfsitl:frame_samples"), 100);
  EXPECT_EQ(an[1].at("rfsitl:dst"), 255);
  EXPECT_NEAR(an[2].at("rfsitl:snr_db").get<double>(), 3.0, 1e-9);
  EXPECT_EQ(an[2].at("core:label"), "3->2 lost:collision");
  EXPECT_EQ(an[4].at("core:label"), "2->1 pending (own)");
  EXPECT_FALSE(an[4].contains("rfsitl:snr_db"));
}

TEST(SigmfRecorder, StopsAtMaxBytesAndSaysTruncated) {
  TempDir dir;
  SigmfSettings s;
  s.directory = dir.path();
  s.nodes = {3};
  s.start_s = 0.0;
  s.duration_s = 1e-3;        // 1000 samples
  s.max_bytes = 8 * 120 + 5;  // room for 120 samples
  auto rec = make_sigmf_recorder(s, three_nodes());
  using K = FrameEventKind;
  rec->on_frame_event(ev(K::kTransmitted, 100, 1, 3, 1, 0x00000000, 50));  // cut at 120
  rec->on_frame_event(ev(K::kTransmitted, 150, 2, 3, 2, 0x01000000, 50));  // after the cut
  run_ticks(*rec, 2, {0, 100});
  EXPECT_FALSE(rec->wants_samples(2, 200, kTick)) << "full: no more samples wanted";
  run_ticks(*rec, 2, {200, 300});
  EXPECT_EQ(rec->samples_written(3), 120U);
  rec->finish();

  const auto data = read_data(dir.path("node3.sigmf-data"));
  ASSERT_EQ(data.size(), 120U);
  EXPECT_EQ(data.back(), value_at(119));
  const json meta = read_meta(dir.path("node3.sigmf-meta"));
  EXPECT_EQ(meta.at("global").at("rfsitl:truncated"), true);
  EXPECT_EQ(meta.at("global").at("rfsitl:recorded_samples"), 120);
  const json& an = meta.at("annotations");
  ASSERT_EQ(an.size(), 1U) << an.dump(2);
  EXPECT_EQ(an[0].at("core:sample_start"), 100);
  EXPECT_EQ(an[0].at("core:sample_count"), 20);
  EXPECT_EQ(an[0].at("rfsitl:outcome"), "pending");
}

TEST(SigmfRecorder, MissingTicksStartANewCaptureSegment) {
  TempDir dir;
  SigmfSettings s;
  s.directory = dir.path();
  s.nodes = {1};
  s.duration_s = 1e-3;
  auto rec = make_sigmf_recorder(s, three_nodes());
  rec->on_frame_event(ev(FrameEventKind::kTransmitted, 150, 2, 1, 2, 0x01000000, 200));
  run_ticks(*rec, 0, {0, 100, 300});  // the tick at 200 never came
  rec->finish();
  const auto data = read_data(dir.path("node1.sigmf-data"));
  ASSERT_EQ(data.size(), 300U);
  EXPECT_EQ(data[199], value_at(199));
  EXPECT_EQ(data[200], value_at(300));
  const json meta = read_meta(dir.path("node1.sigmf-meta"));
  const json& caps = meta.at("captures");
  ASSERT_EQ(caps.size(), 2U);
  EXPECT_EQ(caps[1].at("core:sample_start"), 200);
  EXPECT_EQ(caps[1].at("core:global_index"), 300);
  // The frame [150, 350) is split at the gap.
  const json& an = meta.at("annotations");
  ASSERT_EQ(an.size(), 2U) << an.dump(2);
  EXPECT_EQ(an[0].at("core:sample_start"), 150);
  EXPECT_EQ(an[0].at("core:sample_count"), 50);
  EXPECT_EQ(an[1].at("core:sample_start"), 200);
  EXPECT_EQ(an[1].at("core:sample_count"), 50);
}

TEST(SigmfRecorder, SeveralNodesAndMetaWrittenOnDestruction) {
  TempDir dir;
  SigmfSettings s;
  s.directory = dir.path();
  s.nodes = {3, 1, 3};
  s.duration_s = 200e-6;
  {
    auto rec = make_sigmf_recorder(s, three_nodes());
    EXPECT_TRUE(rec->wants_samples(0, 0, kTick));
    EXPECT_FALSE(rec->wants_samples(1, 0, kTick));
    EXPECT_TRUE(rec->wants_samples(2, 0, kTick));
    run_ticks(*rec, 0, ticks_until(500));
    run_ticks(*rec, 2, {0});
  }
  EXPECT_EQ(read_data(dir.path("node1.sigmf-data")).size(), 200U);
  EXPECT_EQ(read_data(dir.path("node3.sigmf-data")).size(), 100U);
  EXPECT_EQ(read_meta(dir.path("node1.sigmf-meta")).at("global").at("rfsitl:node_id"), 1);
  const json m3 = read_meta(dir.path("node3.sigmf-meta"));
  EXPECT_EQ(m3.at("global").at("rfsitl:node_id"), 3);
  EXPECT_EQ(m3.at("annotations").size(), 0U);
}

TEST(SigmfRecorder, UnknownNodeAndUnwritableDirectoryThrow) {
  TempDir dir;
  SigmfSettings s;
  s.directory = dir.path("ok");
  s.nodes = {2, 9};
  try {
    make_sigmf_recorder(s, three_nodes());
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("node 9"), std::string::npos) << e.what();
  }
  fs::create_directories(dir.path());
  std::ofstream(dir.path("file")) << "x";
  s.nodes = {2};
  s.directory = dir.path("file/sub");
  try {
    make_sigmf_recorder(s, three_nodes());
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(s.directory), std::string::npos) << e.what();
  }
}

TEST(SigmfRecorder, AFullDiskStopsThatNodesRecordingAndTheSummarySaysWhy) {
  TempDir dir;
  fs::create_directories(dir.path());
  // Node 1's data goes to /dev/full (opens, then refuses every write with
  // ENOSPC: a full disk); node 3's to a file.
  fs::create_symlink("/dev/full", dir.path("node1.sigmf-data"));
  SigmfSettings s;
  s.directory = dir.path();
  s.nodes = {1, 3};
  s.duration_s = 0.05;  // 50000 samples, 400 KB: more than the write buffer holds
  auto rec = make_sigmf_recorder(s, three_nodes());
  const auto ticks = ticks_until(50000);
  run_ticks(*rec, 0, ticks);
  run_ticks(*rec, 2, ticks);
  EXPECT_FALSE(rec->wants_samples(0, 40000, kTick)) << "a failed node wants no more samples";
  rec->finish();
  const json j = rec->summary();
  EXPECT_EQ(j.at("directory"), dir.path());
  ASSERT_EQ(j.at("nodes").size(), 2U);
  const json& n1 = j.at("nodes")[0];
  EXPECT_EQ(n1.at("id"), 1);
  EXPECT_EQ(n1.at("stopped"), true);
  EXPECT_EQ(n1.at("error"), "No space left on device");
  EXPECT_LT(n1.at("samples_written").get<std::uint64_t>(), 50000U);
  EXPECT_EQ(n1.at("meta_written"), true);
  EXPECT_EQ(read_meta(dir.path("node1.sigmf-meta")).at("global").at("rfsitl:error"),
            "No space left on device");
  EXPECT_EQ(j.at("nodes")[1], json({{"id", 3},
                                    {"data", dir.path("node3.sigmf-data")},
                                    {"samples_written", 50000},
                                    {"truncated", false},
                                    {"stopped", false},
                                    {"error", nullptr},
                                    {"meta_written", true}}));
}

}  // namespace
}  // namespace rfsitl::monitor
