#pragma once
/// A channel stage: one effect of the air on a link, a small component with its
/// own declared settings, registered by name (registry/channel_stage_registry.hpp)
/// and listed in the scenario's `channel.stages`, applied in that order.
///
/// Each stage gives every link a complex amplitude factor from the link's
/// geometry: large-scale stages (path loss, shadowing, antennas, occlusion)
/// when a node moves, time-varying ones (fading) on a finer grid in time. A
/// chain of them multiplies, so their gains in dB add (link_budget.hpp).
#include <complex>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/config/settings.hpp"

namespace rfsitl::channel {

/// One path of a dispersive link: how late it arrives and with what amplitude.
struct Path {
  double delay_s = 0.0;             ///< after the transmission, >= 0
  std::complex<double> gain = 1.0;  ///< |gain|^2: the path's share of the power
};

/// A stage that scales each link by a factor that depends on its geometry only.
class GainStage {
 public:
  virtual ~GainStage() = default;

  /// The link's complex amplitude factor: |g|^2 is its power gain (a loss is
  /// below 1), arg(g) its phase shift. Pure: the same geometry always gives the
  /// same value. Thread-safe (const). Called when a node moves, O(N) per move.
  virtual std::complex<double> gain(const LinkGeometry& link) const = 0;

  /// True when every link has the gain of its reverse (the matrix then
  /// evaluates each pair once). Antennas that point somewhere are not.
  virtual bool reciprocal() const { return true; }

  /// False (large-scale stages): the gain is evaluated when a node moves and
  /// held until the next move. True (fast fading): the gain changes as the
  /// ends move by fractions of a wavelength, so it is evaluated on a grid of
  /// update_interval_s() with each end's position extrapolated along its
  /// velocity, and interpolated linearly between grid points.
  virtual bool time_varying() const { return false; }

  /// Time-varying stages: the grid's spacing in seconds (well below the
  /// coherence time).
  virtual double update_interval_s() const { return 0.0; }

  /// True when the gain depends on the ends' attitudes (antennas, airframe
  /// occlusion): the matrix then re-evaluates a node's links when it turns.
  virtual bool depends_on_attitude() const { return false; }

  /// True for a stage that splits a link into delayed paths (paths()). Its
  /// gain() must then be the root of the paths' total power, sqrt(sum |g_p|^2):
  /// what the link budget, the frame ledger and the dashboard see of it.
  virtual bool dispersive() const { return false; }

  /// Dispersive stages: appends the link's paths to `out` (at least one).
  /// Pure and thread-safe, like gain(); called when a node moves.
  virtual void paths(const LinkGeometry& link, std::vector<Path>& out) const {
    out.push_back({0.0, gain(link)});
  }
};

/// What a stage may need beyond its settings.
struct StageContext {
  double carrier_hz = 2.4e9;     ///< the radio's carrier (radio.carrier_hz)
  std::uint64_t seed = 1;        ///< the scenario's seed, for stages with random draws
  std::size_t position = 0;      ///< the stage's place in channel.stages (keys its random streams)
  std::string source_dir;        ///< the scenario file's folder: data files are relative to it
  std::vector<NodeId> node_ids;  ///< index -> the node's id (data files name nodes by id)
  double sample_rate_hz = 1e6;   ///< the emulator's (time.sample_rate_hz)
};

/// A registered stage: its self-description and how to build it from checked
/// settings (they passed info.validate()). make may throw std::invalid_argument
/// for what only building finds out (e.g. a data file that does not parse).
struct ChannelStageComponent {
  config::ComponentInfo info;  ///< kind "channel"
  std::function<std::unique_ptr<GainStage>(const config::Settings&, const StageContext&)> make;
};

}  // namespace rfsitl::channel
