#pragma once
/// The live link table: for each ordered pair of nodes (tx -> rx) its
/// distance, path gain, SNR, the receiver's declared PER estimate
/// (phy/per_curve.hpp) and the frames decoded and lost on it. The dashboard
/// serves it as GET /api/links (what `rfsitl links` prints) and exports part
/// of it in /metrics. Pure functions of what they are given: any thread.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/phy/per_curve.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor {

/// One ordered pair.
struct LinkRow {
  NodeId tx = 0;
  NodeId rx = 0;
  std::optional<double> distance_m;  ///< nullopt while either position is unknown
  std::optional<double> gain_db;     ///< |c|^2 in dB, fading included; nullopt: no link
  std::optional<double> snr_db;      ///< gain over the noise variance; nullopt: no link or no noise
  std::optional<double> per;         ///< receiver's declared PER at snr_db; nullopt: no estimate
  std::uint32_t received = 0;        ///< frames tx -> rx decoded (LiveView)
  std::uint32_t lost = 0;            ///< frames tx -> rx lost
};

/// What the rows are computed from, all by node index (engine order).
struct LinkInputs {
  std::span<const NodeId> ids;
  std::span<const std::optional<Ecef>> positions;  ///< shorter than ids: the rest unknown
  std::span<const float> gains;                    ///< row-major [tx * N + rx], |c|^2
  double noise_variance = 0.0;                     ///< per sample; 0: noise-free
  const LiveView::LinkOutcomes* outcomes = nullptr;
  std::span<const phy::PerCurve> curves;  ///< by receiver; empty function: no estimate
  std::size_t payload_bytes = 80;         ///< the frame size the PER is estimated for
};

/// Every ordered pair (tx != rx), tx-major in node order.
std::vector<LinkRow> link_rows(const LinkInputs& in);

/// Each node's declared PER curve (its receiver's PHY with its settings); an
/// empty function for a node without one (another program's transceiver).
std::vector<phy::PerCurve> declared_per_curves(const scenario::Scenario& s);

/// Which rows a reader wants (GET /api/links?payload=..&top=..&worst=..&min_snr_db=..).
struct LinkQuery {
  std::size_t payload_bytes = 80;    ///< 1..65535
  std::size_t top = 0;               ///< >0: only the `top` links of highest SNR, best first
  std::size_t worst = 0;             ///< >0: only the `worst` links of lowest SNR, worst first
  std::optional<double> min_snr_db;  ///< only links with an SNR of at least this
};

/// Reads a request's query string (without '?'; outside input). nullopt with
/// `error` set when a parameter is unknown, repeated, or out of range (top
/// and worst together too).
std::optional<LinkQuery> parse_link_query(std::string_view query, std::string& error);

/// `rows` as `q` selects them: the SNR floor, then top or worst by SNR (links
/// without an SNR last for top, left out for worst), else node order.
std::vector<LinkRow> select_links(std::vector<LinkRow> rows, const LinkQuery& q);

/// The /api/links document: {"nodes": N, "payload_bytes", "noise_db",
/// "links_total": N (N - 1), "links": [{tx, rx, distance_m, gain_db, snr_db,
/// per, received, lost}, ...]}; null for what a row does not have.
nlohmann::json link_table_json(std::span<const LinkRow> rows, std::size_t nodes, const LinkQuery& q,
                               double noise_variance);

/// The /api/links document as `rfsitl links` prints it: one header line, then
/// a line per link. `doc` is outside input (what a server sent): nullopt with
/// `error` set when it is not such a document.
std::optional<std::string> link_table_text(std::string_view doc, std::string& error);

/// Up to this many nodes /metrics exports every link; above it only the
/// kMetricsTopLinks links of highest SNR, so that a scrape stays bounded
/// (32 nodes have 32 * 31 = 992 links: the most series a scrape carries).
inline constexpr std::size_t kMetricsAllLinksUpToNodes = 32;
inline constexpr std::size_t kMetricsTopLinks = 992;

/// rfsitl_link_snr_db{tx,rx}, rfsitl_link_gain_db, rfsitl_link_per_estimate
/// (gauges, where defined) and rfsitl_link_frames_total{tx,rx,outcome=
/// "received"|"lost"} for every link of `rows` (every ordered pair of
/// `nodes` nodes), or the kMetricsTopLinks best by SNR above
/// kMetricsAllLinksUpToNodes nodes.
void write_link_metrics(std::ostream& o, std::vector<LinkRow> rows, std::size_t nodes);

}  // namespace rfsitl::monitor
