#pragma once
/// The trace stage: replays measured or ray-traced channels (Sionna RT, a
/// channel sounder) as per-link time series of gain (dB) and phase (degrees).
/// Formats, settings and a worked example: docs/channel_traces.md.
///
/// Files. `file` names the trace, relative to the scenario's folder; its
/// extension picks the format:
///  - `.csv`: a header line `t_s,tx,rx,gain_db,phase_deg`, then one row per
///    sample. tx and rx are node IDS as in the scenario. Rows of one link are
///    in time order (equal times are a step: the later row holds from then
///    on); rows of different links may interleave. Blank lines and lines that
///    start with '#' are skipped.
///  - `.npy`: a little-endian float32 or float64 array, C order, of shape
///    (T, L, 2): [k, l] = (gain_db, phase_deg) of link l at t = k * step_s.
///    `links_file` (CSV, header `tx,rx`) lists the L links in array order.
/// Limits: t_s in [0, 1e9], gain_db in [-300, 100], |phase_deg| <= 1e9, files
/// at most kMaxFileBytes. No row may have tx == rx.
///
/// Model. At virtual time t a link's gain is 10^(G(t) / 20) exp(j P(t) pi / 180),
/// G and P interpolated linearly between the link's samples. P is the phase
/// unwrapped along the link's samples (each step taken as the shorter way
/// round, in [-180, 180) degrees), so the file must sample the phase at least
/// twice per turn. Before a link's first sample it holds the first value,
/// after its last the last value. `loop`: the whole file repeats with period
/// t_last - t_first (over all links), time folded into [t_first, t_last)
/// once it passes t_first: a seamless loop repeats its first row at the end.
/// `reciprocal`: a link (a, b) drives (b, a) too when the file has no rows
/// for (b, a). Links the file does not drive get `missing`: unity (gain 1) or
/// block (gain 0). A node's link to itself is always 1.
///
/// Time. time_varying(): the engine evaluates the gain on a grid of
/// 1 / update_rate_hz seconds and interpolates between grid points, so the
/// rate should be at least the trace's own sample rate.
///
/// Errors. A file that does not parse throws std::invalid_argument naming it:
/// "name:line: reason" (CSV) or "name: byte N (field): reason" (NPY).
#include <complex>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/fields.hpp"

namespace rfsitl::channel {

enum class TraceMissing { kUnity, kBlock };

struct TraceSettings {
  std::string file;                             ///< .csv or .npy, relative to the scenario
  std::string links_file;                       ///< .npy only: the links in array order
  double step_s = 0.0;                          ///< .npy only: time between rows, > 0
  double update_rate_hz = 1000.0;               ///< the grid on which gains are computed
  bool loop = false;                            ///< repeat the trace after its end
  TraceMissing missing = TraceMissing::kUnity;  ///< links the file does not drive
  bool reciprocal = true;                       ///< (a, b) drives (b, a) if the file lacks it
};

const config::Fields<TraceSettings>& trace_fields();
ChannelStageComponent trace_component();

namespace trace {

/// The largest trace (or links) file accepted, bytes.
inline constexpr std::size_t kMaxFileBytes = std::size_t{256} << 20;
inline constexpr double kMaxTimeS = 1e9;
inline constexpr double kMinGainDb = -300.0;
inline constexpr double kMaxGainDb = 100.0;
inline constexpr double kMaxPhaseDeg = 1e9;  ///< |phase_deg| at most this

/// One sample of a link, as the file gives it (phase not unwrapped).
struct Sample {
  double t_s = 0.0;
  double gain_db = 0.0;
  double phase_deg = 0.0;
};

/// A directed link by node ids.
struct LinkIds {
  NodeId tx = 0;
  NodeId rx = 0;
  bool operator==(const LinkIds&) const = default;
};

/// One link's samples, t_s non-decreasing, at least one.
struct LinkTrace {
  LinkIds link;
  std::vector<Sample> samples;
};

/// A parsed file: distinct links, each with its samples.
struct Trace {
  std::vector<LinkTrace> links;
};

/// The CSV format above. `name` prefixes every error ("name:line: reason");
/// `node_ids` are the scenario's ids (a row naming another is refused).
/// Throws std::invalid_argument only. Pure, thread-safe.
Trace parse_csv(std::string_view text, const std::string& name, std::span<const NodeId> node_ids);

/// A links file: header `tx,rx`, then one distinct link per line. Errors as parse_csv's.
std::vector<LinkIds> parse_links_csv(std::string_view text, const std::string& name,
                                     std::span<const NodeId> node_ids);

/// The NPY format above (format versions 1.0 and 2.0) with `links` in array
/// order and rows `step_s` apart (> 0). Errors name the byte offset and the
/// header field or sample at fault. Throws std::invalid_argument only.
Trace parse_npy(std::span<const std::uint8_t> bytes, const std::string& name,
                std::span<const LinkIds> links, double step_s);

/// Reads and parses settings.file (and links_file), relative to `source_dir`
/// unless absolute. Throws std::invalid_argument naming the file (unreadable,
/// too large, unknown extension, or what the parser refuses).
Trace load(const TraceSettings& settings, const std::string& source_dir,
           std::span<const NodeId> node_ids);

/// The stage replaying `trace` for a scenario whose node at index i has id
/// node_ids[i]. Preconditions: settings within their limits; `trace` as the
/// parsers return it for these node_ids (ids unique). The stage is immutable
/// and thread-safe.
std::unique_ptr<GainStage> make_stage(const TraceSettings& settings, Trace trace,
                                      std::span<const NodeId> node_ids);

}  // namespace trace
}  // namespace rfsitl::channel
