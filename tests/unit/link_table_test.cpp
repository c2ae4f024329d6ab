/// The live link table (monitor/link_table.hpp): rows from positions, gains,
/// outcomes and PER curves; queries; the text `rfsitl links` prints; and the
/// per-link series of /metrics with their bound.
#include "rfsitl/monitor/link_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace rfsitl::monitor {
namespace {

/// N nodes (ids 1..N) on a line 100 m apart; link t -> r has gain
/// 10^-(6 + (t*N+r)/(N*N)) so every link's SNR differs; noise 1e-9.
struct Line {
  explicit Line(std::size_t nodes) : n(nodes) {
    for (std::size_t i = 0; i < n; ++i) {
      ids.push_back(static_cast<NodeId>(i + 1));
      positions.push_back(Ecef{100.0 * static_cast<double>(i), 0, 0});
    }
    gains.resize(n * n);
    outcomes.received.resize(n * n);
    outcomes.lost.resize(n * n);
    for (std::size_t k = 0; k < n * n; ++k) {
      gains[k] = static_cast<float>(
          std::pow(10.0, -6.0 - static_cast<double>(k) / static_cast<double>(n * n)));
      outcomes.received[k] = static_cast<std::uint32_t>(k);
      outcomes.lost[k] = static_cast<std::uint32_t>(2 * k);
    }
  }
  LinkInputs inputs() const { return {ids, positions, gains, 1e-9, &outcomes, curves, 80}; }
  std::size_t n;
  std::vector<NodeId> ids;
  std::vector<std::optional<Ecef>> positions;
  std::vector<float> gains;
  LiveView::LinkOutcomes outcomes;
  std::vector<phy::PerCurve> curves;
};

TEST(LinkTable, RowsCarryDistanceGainSnrPerAndOutcomesOfEachOrderedPair) {
  Line l(3);
  l.positions[2].reset();  // node 3's position unknown
  // Receiver 2's curve reports the SNR and size it was asked about.
  l.curves.resize(3);
  l.curves[1] = [](double snr_db, std::size_t bytes) {
    return snr_db / 1000.0 + static_cast<double>(bytes) * 1e-6;
  };
  const auto rows = link_rows(l.inputs());
  ASSERT_EQ(rows.size(), 6U);
  const LinkRow& r12 = rows[0];
  EXPECT_EQ(r12.tx, 1);
  EXPECT_EQ(r12.rx, 2);
  ASSERT_TRUE(r12.distance_m.has_value());
  EXPECT_NEAR(*r12.distance_m, 100.0, 1e-9);
  const double gain_db = 10.0 * std::log10(static_cast<double>(l.gains[1]));
  EXPECT_NEAR(*r12.gain_db, gain_db, 1e-6);
  EXPECT_NEAR(*r12.snr_db, gain_db + 90.0, 1e-6);
  ASSERT_TRUE(r12.per.has_value());
  EXPECT_NEAR(*r12.per, *r12.snr_db / 1000.0 + 80e-6, 1e-12);
  EXPECT_EQ(r12.received, l.outcomes.received[1]);
  EXPECT_EQ(r12.lost, l.outcomes.lost[1]);
  for (const LinkRow& r : rows) {
    EXPECT_NE(r.tx, r.rx);
    EXPECT_EQ(r.distance_m.has_value(), r.tx != 3 && r.rx != 3);
    EXPECT_EQ(r.per.has_value(), r.rx == 2);  // only node 2 has a curve
  }
  // No gain: no SNR and no PER; noise-free: a gain but no SNR.
  l.gains[1] = 0.0F;
  EXPECT_FALSE(link_rows(l.inputs())[0].gain_db.has_value());
  EXPECT_FALSE(link_rows(l.inputs())[0].per.has_value());
  LinkInputs noise_free = l.inputs();
  noise_free.noise_variance = 0.0;
  EXPECT_TRUE(link_rows(noise_free)[1].gain_db.has_value());
  EXPECT_FALSE(link_rows(noise_free)[1].snr_db.has_value());
}

TEST(LinkTable, TopWorstAndTheSnrFloorSelectByOrder) {
  const Line l(4);
  const auto rows = link_rows(l.inputs());
  std::vector<double> snrs;
  for (const LinkRow& r : rows) snrs.push_back(*r.snr_db);
  std::sort(snrs.rbegin(), snrs.rend());
  LinkQuery top;
  top.top = 3;
  const auto best = select_links(rows, top);
  ASSERT_EQ(best.size(), 3U);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(*best[i].snr_db, snrs[i]);
  LinkQuery worst;
  worst.worst = 2;
  const auto low = select_links(rows, worst);
  ASSERT_EQ(low.size(), 2U);
  EXPECT_EQ(*low[0].snr_db, snrs.back());
  EXPECT_EQ(*low[1].snr_db, snrs[snrs.size() - 2]);
  LinkQuery floor;
  floor.min_snr_db = snrs[4];
  const auto above = select_links(rows, floor);
  EXPECT_EQ(above.size(), 5U);
  for (const LinkRow& r : above) EXPECT_GE(*r.snr_db, snrs[4]);
}

TEST(LinkTable, QueriesParseOrSayWhatIsWrong) {
  std::string error;
  const auto q = parse_link_query("payload=200&top=5&min_snr_db=-3.5", error);
  ASSERT_TRUE(q.has_value()) << error;
  EXPECT_EQ(q->payload_bytes, 200U);
  EXPECT_EQ(q->top, 5U);
  EXPECT_EQ(*q->min_snr_db, -3.5);
  EXPECT_TRUE(parse_link_query("", error).has_value());
  for (const char* bad : {"payload=0", "payload=65536", "top=x", "top=5&top=6", "colour=red",
                          "top=1&worst=1", "min_snr_db=", "min_snr_db=nan", "worst=-1"}) {
    error.clear();
    EXPECT_FALSE(parse_link_query(bad, error).has_value()) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
}

TEST(LinkTable, TheDocumentReadsBackAsTheTableRfsitlLinksPrints) {
  Line l(3);
  l.positions[2].reset();
  const auto rows = link_rows(l.inputs());
  const std::string doc = link_table_json(rows, 3, LinkQuery{}, 1e-9).dump();
  std::string error;
  const auto text = link_table_text(doc, error);
  ASSERT_TRUE(text.has_value()) << error;
  EXPECT_EQ(text->rfind("links: 6 of 6 (3 nodes), PER estimated for 80-byte frames\n", 0), 0U)
      << *text;
  std::istringstream in(*text);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 2U + rows.size());
  // "   1 ->   2       100.0 ..." with its counts at the end; "-" where unknown.
  EXPECT_EQ(lines[2].rfind("   1 ->   2       100.0", 0), 0U) << lines[2];
  EXPECT_NE(
      lines[2].find(std::to_string(rows[0].received) + "         " + std::to_string(rows[0].lost)),
      std::string::npos)
      << lines[2];
  EXPECT_EQ(lines[3].rfind("   1 ->   3           -", 0), 0U) << lines[3];
  for (const char* bad : {"", "[]", "{\"nodes\":2}", R"({"nodes":2,"payload_bytes":80,
        "links_total":2,"links":[{"tx":1,"rx":2,"received":1,"lost":-1}]})",
                          R"({"nodes":2,"payload_bytes":80,"links_total":2,
        "links":[{"tx":1,"rx":2,"received":1,"lost":0,"snr_db":"high"}]})"}) {
    error.clear();
    EXPECT_FALSE(link_table_text(bad, error).has_value()) << bad;
    EXPECT_NE(error.find("not a link table"), std::string::npos) << error;
  }
}

/// The (tx, rx) pairs of the rfsitl_link_snr_db series in `text`, and checks
/// every frames series comes as a received/lost pair.
std::set<std::pair<int, int>> snr_series(const std::string& text, std::size_t& frames_series) {
  std::set<std::pair<int, int>> out;
  frames_series = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    int tx = 0;
    int rx = 0;
    if (std::sscanf(line.c_str(), "rfsitl_link_snr_db{tx=\"%d\",rx=\"%d\"}", &tx, &rx) == 2) {
      out.emplace(tx, rx);
    }
    if (line.rfind("rfsitl_link_frames_total{", 0) == 0) ++frames_series;
  }
  return out;
}

TEST(LinkTable, MetricsExportEveryLinkUpTo32NodesThenTheTopKBySnr) {
  {
    const Line l(kMetricsAllLinksUpToNodes);
    std::ostringstream o;
    write_link_metrics(o, link_rows(l.inputs()), l.n);
    std::size_t frames = 0;
    EXPECT_EQ(snr_series(o.str(), frames).size(), l.n * (l.n - 1));
    EXPECT_EQ(frames, 2 * l.n * (l.n - 1));
    // Node 1 -> 2 (k = 1): its counts under its labels.
    EXPECT_NE(o.str().find("rfsitl_link_frames_total{tx=\"1\",rx=\"2\",outcome=\"received\"} 1\n"
                           "rfsitl_link_frames_total{tx=\"1\",rx=\"2\",outcome=\"lost\"} 2\n"),
              std::string::npos);
    EXPECT_NE(o.str().find("# TYPE rfsitl_link_frames_total counter\n"), std::string::npos);
    EXPECT_NE(o.str().find("# TYPE rfsitl_link_snr_db gauge\n"), std::string::npos);
  }
  const Line l(40);
  const auto rows = link_rows(l.inputs());
  std::ostringstream o;
  write_link_metrics(o, rows, l.n);
  std::size_t frames = 0;
  const auto exported = snr_series(o.str(), frames);
  ASSERT_EQ(exported.size(), kMetricsTopLinks);
  EXPECT_EQ(frames, 2 * kMetricsTopLinks);
  // Every exported link is at least as good as every link left out.
  double worst_in = INFINITY;
  double best_out = -INFINITY;
  for (const LinkRow& r : rows) {
    const bool in = exported.count({r.tx, r.rx}) > 0;
    (in ? worst_in : best_out) = in ? std::min(worst_in, *r.snr_db) : std::max(best_out, *r.snr_db);
  }
  EXPECT_GE(worst_in, best_out);
  EXPECT_NE(o.str().find("Above 32 nodes only the 992 links of highest SNR."), std::string::npos);
}

}  // namespace
}  // namespace rfsitl::monitor
