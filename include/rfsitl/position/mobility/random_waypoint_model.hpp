#pragma once
/// The random waypoint model: straight legs to uniformly drawn points of a box,
/// each at a uniformly drawn speed, with a pause at every point.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

#include "rfsitl/position/mobility/box.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility {

struct RandomWaypointSettings {
  Box box;                      ///< every position stays inside (validate: non-empty axes)
  double speed_min_mps = 1.0;   ///< > 0 (a zero minimum makes the mean leg time infinite)
  double speed_max_mps = 10.0;  ///< >= speed_min_mps
  double pause_s = 0.0;         ///< at every destination, >= 0
  std::uint64_t seed = 1;       ///< the whole track follows from it
  /// Where the node is at t <= 0 and the first leg starts (inside the box);
  /// unset: drawn uniformly from the box, from the seed.
  std::optional<LocalPosition> start;

  /// Throws std::invalid_argument naming the field ("random_waypoint.speed_min_mps
  /// must be > 0 (got 0)"); a box that is one point needs pause_s > 0.
  void validate() const;
};

/// Leg k leaves its start point at time T_k (T_0 = 0), flies straight to a
/// destination drawn uniformly from the box at a speed drawn uniformly from
/// [speed_min, speed_max], waits pause_s there, and leg k + 1 leaves from it.
/// Before t = 0 the node is at the start point.
///
/// Draws come from a generator of this library's own (not <random>'s
/// distributions, which differ between standard libraries), so a seed gives the
/// same track with any compiler. Legs are generated lazily and cached (a window
/// of the most recent ones): evaluating at non-decreasing times costs amortised
/// O(1); a time before the window regenerates from the seed, a time far ahead
/// costs the legs in between.
class RandomWaypointModel final : public MobilityModel {
 public:
  /// Validates `settings`.
  explicit RandomWaypointModel(const RandomWaypointSettings& settings);
  ~RandomWaypointModel() override;
  RandomWaypointModel(RandomWaypointModel&&) noexcept;
  RandomWaypointModel& operator=(RandomWaypointModel&&) noexcept;

  MotionState state_at(double t_s) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rfsitl::position::mobility
