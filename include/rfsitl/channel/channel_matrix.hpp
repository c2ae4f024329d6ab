#pragma once
/// The N x N matrix of link coefficients, kept in step with node positions.
#include <complex>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rfsitl/channel/link_budget.hpp"
#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::channel {

/// A dispersive link's impulse response on the sample grid: its paths, each
/// with its fractional-delay filter (fractional_delay.hpp), laid over the
/// distinct lags they cover.
struct LinkResponse {
  std::vector<std::uint32_t> lags;  ///< samples, ascending, distinct
  std::vector<cf32> taps;           ///< the response at each lag: sum over paths of gain x filter
  std::vector<cf32> path_gains;     ///< each path's gain (every large-scale stage included)
  /// Path p's filter at lags[k]: path_filters[p * lags.size() + k] (0 where it has no tap).
  std::vector<float> path_filters;
};

/// Owned by the engine thread; not thread-safe. Node indices are 0..N-1.
class ChannelMatrix {
 public:
  /// Precondition: budget != nullptr. All nodes start without a position (no
  /// links). `origin` is where the local frame that stages see is centred.
  /// `sample_rate_hz` turns dispersive links' delays into samples.
  ChannelMatrix(std::size_t num_nodes, std::shared_ptr<const LinkBudget> budget,
                const GeodeticPosition& origin = {}, double sample_rate_hz = 1e6);

  std::size_t size() const { return n_; }

  /// Sets or clears (nullopt) node `i`'s position and recomputes its row and column.
  /// A node without a known position has coefficient 0 to and from every node,
  /// itself included.
  void set_position(std::size_t i, std::optional<Ecef> pos);

  const std::optional<Ecef>& position(std::size_t i) const { return positions_[i]; }

  /// Coefficient of the link from transmitter `tx` to receiver `rx`.
  cf32 coefficient(std::size_t tx, std::size_t rx) const { return coeff_[rx * n_ + tx]; }

  /// Power gain of the link from `tx` to `rx`: |c|^2 times band_gain(), what
  /// reaches the receiver's band (the ledger's SNR, the link table).
  float power_gain(std::size_t tx, std::size_t rx) const {
    return std::norm(coefficient(tx, rx)) * band_gain(tx, rx);
  }

  /// The fraction of tx's power inside rx's band (radio_tuning.hpp's kappa):
  /// 1 for every link until set_band_gain() (radios sharing one band).
  float band_gain(std::size_t tx, std::size_t rx) const {
    return band_gain_.empty() ? 1.0F : band_gain_[rx * n_ + tx];
  }
  void set_band_gain(std::size_t tx, std::size_t rx, float kappa);

  /// Row of coefficients seen by receiver `rx`, indexed by transmitter.
  std::span<const cf32> receiver_row(std::size_t rx) const { return {coeff_.data() + rx * n_, n_}; }

  // ---- dispersive stages (delay, multipath) -------------------------------------

  /// True when some stage splits links into delayed paths: response() then
  /// holds each link's impulse response, and coefficient() its root total power
  /// gain (what the ledger and the dashboard use).
  bool dispersive() const { return budget_->dispersive(); }

  /// The response of the link tx -> rx. Precondition: dispersive(). Empty (no
  /// lags) when either end has no position.
  const LinkResponse& response(std::size_t tx, std::size_t rx) const {
    return responses_[rx * n_ + tx];
  }

  /// The longest lag, samples, of any link's response so far (it never
  /// shrinks): how far back a transmitter's samples still reach a receiver.
  std::uint32_t max_lag() const { return max_lag_; }

  /// Distance in metres, or nullopt when either position is unknown.
  std::optional<double> distance(std::size_t a, std::size_t b) const;

  // ---- time-varying stages (fading) ---------------------------------------------

  /// True when the chain has time-varying stages: a link's coefficient then
  /// changes between position updates (coefficient_at).
  bool time_varying() const { return budget_->time_varying(); }

  /// True when some stage depends on the nodes' attitudes.
  bool depends_on_attitude() const { return budget_->depends_on_attitude(); }

  /// The grid on which time-varying gains are computed, seconds (0: none).
  double update_interval_s() const { return budget_->update_interval_s(); }

  /// The virtual time, seconds, with which set_position stamps positions.
  void set_clock(double now_s) { clock_s_ = now_s; }

  /// Node `i`'s velocity (local east/north/up, m/s), along which its position
  /// is extrapolated for time-varying stages. Starts at zero.
  void set_velocity(std::size_t i, const LocalVelocity& v) { velocity_.at(i) = v; }

  /// Node `i`'s attitude (nullopt: never reported), for stages that depend on
  /// where a body points (antennas, airframe occlusion); recomputes its row
  /// and column when the chain has such a stage.
  void set_attitude(std::size_t i, const std::optional<Orientation>& a);

  /// The coefficient of the link tx -> rx at virtual time t_s: coefficient()
  /// times the time-varying stages' gains with both ends extrapolated from
  /// their last positions along their velocities. Thread-safe against other
  /// const calls.
  cf32 coefficient_at(std::size_t tx, std::size_t rx, double t_s) const;

  /// The time-varying stages' factor for path `path` of the link tx -> rx at
  /// t_s (1 when none is time-varying): coefficient_at() is coefficient()
  /// times this for path 0. Thread-safe against other const calls.
  std::complex<double> fading_at(std::size_t tx, std::size_t rx, double t_s,
                                 std::size_t path) const;

  /// The same for paths first_path, first_path + 1, ... into `out` (one per
  /// element), with the link's geometry built once for all of them.
  void fading_at(std::size_t tx, std::size_t rx, double t_s, std::size_t first_path,
                 std::span<std::complex<double>> out) const;

  /// The power gain of the link tx -> rx at virtual time t_s with the
  /// time-varying stages included: what the link delivers at that moment,
  /// where power_gain() is its large-scale value. |coefficient_at()|^2 for a
  /// link of one path; for a dispersive link the sum over its paths p of
  /// |path_gains[p] fading_at(tx, rx, t_s, p)|^2, its instantaneous total
  /// power (the paths fade independently, so it is not path 0's fade applied
  /// to the total). Exactly power_gain() when no stage is time-varying. Costs
  /// one evaluation of the time-varying stages per path (a fading stage: M
  /// sines and cosines and M Philox blocks each). Thread-safe against other
  /// const calls.
  float power_gain_at(std::size_t tx, std::size_t rx, double t_s) const;

 private:
  void recompute(std::size_t i);
  void recompute_response(std::size_t tx, std::size_t rx);
  LinkGeometry geometry(std::size_t tx, std::size_t rx) const;

  std::size_t n_;
  std::shared_ptr<const LinkBudget> budget_;
  GeodeticPosition origin_;
  std::vector<std::optional<Ecef>> positions_;
  std::vector<LocalPosition> local_;  // of the nodes with a position
  std::vector<LocalVelocity> velocity_;
  std::vector<std::optional<Orientation>> attitude_;
  std::vector<double> stamp_s_;  // when each position was set
  double clock_s_ = 0.0;
  std::vector<cf32> coeff_;       // row-major by receiver: coeff_[rx * n + tx]
  std::vector<float> band_gain_;  // as coeff_; empty: 1 everywhere
  double sample_rate_hz_;
  std::vector<LinkResponse> responses_;  // as coeff_; dispersive chains only
  std::uint32_t max_lag_ = 0;
  std::vector<Path> paths_scratch_;
};

}  // namespace rfsitl::channel
