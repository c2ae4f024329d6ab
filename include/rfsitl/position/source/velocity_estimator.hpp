#pragma once
/// Velocity from successive positions, for sources that report none (the
/// location port's formats, the dashboard's drag), so that the channel's
/// Doppler is never silently zero for a moving node.
///
/// The first difference of two reports is the estimate; each later difference
/// is blended in with an exponential moving average of time constant
/// `time_constant_s`: weight 1 - exp(-dt / tau) for a report dt after the last,
/// so that quantised or jittery positions do not make the velocity jump, and
/// the estimate settles to a constant velocity within a few tau. A report more
/// than `max_gap_s` after the last starts over at zero (a jump after silence is
/// a relocation, not motion). Pure; one per node; not thread-safe.
#include <optional>

#include "rfsitl/common/position.hpp"
#include "rfsitl/position/source/node_state.hpp"

namespace rfsitl::position {

class VelocityEstimator {
 public:
  static constexpr double kDefaultTimeConstantS = 1.0;
  static constexpr double kDefaultMaxGapS = 5.0;

  explicit VelocityEstimator(double time_constant_s = kDefaultTimeConstantS,
                             double max_gap_s = kDefaultMaxGapS)
      : tau_s_(time_constant_s), max_gap_s_(max_gap_s) {}

  /// A position (local east/north/up metres) at `t_s` (seconds, not before the
  /// last report's); returns the estimate after it.
  Velocity update(double t_s, const LocalPosition& p);

  /// Forgets the history (the node's position became unknown).
  void reset() {
    last_.reset();
    velocity_ = {};
    have_difference_ = false;
  }

 private:
  struct Fix {
    double t_s;
    LocalPosition p;
  };
  double tau_s_;
  double max_gap_s_;
  std::optional<Fix> last_;
  Velocity velocity_;
  bool have_difference_ = false;
};

}  // namespace rfsitl::position
