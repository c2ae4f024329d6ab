#pragma once
/// The run's state as JSON (`--summary-json`, /api/stats, the dashboard's
/// snapshots) and as Prometheus text (/metrics). Everything is read through the
/// engine's thread-safe views, so any thread may call these during a run.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor {

/// Progress and every node's counters, position (local ENU metres from the
/// scenario's origin and WGS84; null while unknown), velocity and attitude when
/// reported, and its position source with that source's counters (the
/// --summary-json document, /api/stats).
nlohmann::json stats_json(const scenario::Scenario& s, engine::Engine& e,
                          const position::SourceStatusFn& sources = {});

/// stats_json plus `links`: {n, gain_db, snr_db}, row-major [tx * n + rx], each
/// link's power gain |c|^2 in dB (with a `radio` section the received power in
/// dBm) and its SNR, fading included (the gains of the moment, as the
/// dashboard's matrix); null for a node itself and where there is no link. The
/// /api/stats and --summary-json document. Computing the faded gains costs the
/// caller's thread O(N^2) fading evaluations.
nlohmann::json stats_with_links_json(const scenario::Scenario& s, engine::Engine& e,
                                     const position::SourceStatusFn& sources = {});

/// stats_json plus the link matrix as
/// SNR in dB (null: no link; left out when `with_snr` is false, for viewers
/// that have it and nothing moved), each receiver's sensitivity, and the
/// decoded and lost frames per link (the dashboard's snapshot message).
nlohmann::json snapshot_json(const scenario::Scenario& s, engine::Engine& e, const LiveView& view,
                             const std::vector<double>& sensitivity_db, bool control,
                             bool with_snr = true, const position::SourceStatusFn& sources = {});

/// Prometheus text exposition format 0.0.4: every number of stats_json, per
/// node labelled {node="ID"}, each family with its HELP and TYPE lines.
std::string prometheus_text(const scenario::Scenario& s, engine::Engine& e,
                            const position::SourceStatusFn& sources = {});

/// `v` rounded to `decimals` places (multiplying by 10^d, not dividing by
/// 10^-d, keeps the printed number short).
double round_to(double v, int decimals);

/// The shortest text that reads back as `v` (a stream's default 6 digits
/// would print a day of virtual time as 86400 but a month as 2.592e+06);
/// NaN, +Inf, -Inf as the text format spells them.
std::string prometheus_number(double v);

/// A label value as the text format needs it inside double quotes: backslash,
/// double quote and line feed become \\, \" and \n; everything else stays.
std::string prometheus_label_value(std::string_view v);
/// HELP text escaped: backslash and line feed (a double quote stays as is).
std::string prometheus_help_text(std::string_view v);
/// A family's "# HELP" and "# TYPE" lines (`help` escaped).
void prometheus_family(std::ostream& o, std::string_view name, std::string_view type,
                       std::string_view help);

}  // namespace rfsitl::monitor
