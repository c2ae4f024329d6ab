#pragma once
/// The Gauss-Markov model: speed, heading and climb angle that drift around
/// their means with memory, inside a box whose faces reflect the node.
#include <cstdint>
#include <memory>
#include <optional>

#include "rfsitl/position/mobility/box.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility {

struct GaussMarkovSettings {
  Box box;                          ///< every position stays inside
  double alpha = 0.85;              ///< memory in [0, 1]: 0 memoryless, 1 straight lines
  double mean_speed_mps = 10.0;     ///< >= 0
  double mean_direction_rad = 0.0;  ///< heading, counter-clockwise from east
  double mean_pitch_rad = 0.0;      ///< climb angle, in [-pi/2, pi/2]
  double speed_sd_mps = 2.0;        ///< >= 0
  double direction_sd_rad = 0.5;    ///< >= 0
  double pitch_sd_rad = 0.0;        ///< >= 0 (0 with mean 0: level flight)
  double update_interval_s = 1.0;   ///< > 0
  std::uint64_t seed = 1;
  /// Position at t <= 0 (inside the box); unset: drawn uniformly from the box.
  std::optional<LocalPosition> start;

  /// Throws std::invalid_argument naming the field ("gauss_markov.alpha must be
  /// in [0, 1] (got 1.5)").
  void validate() const;
};

/// Every update_interval_s (at t_n = n * interval) the node's speed s, heading d
/// and pitch p are redrawn, with w standard normal draws:
///   s_n = a s_(n-1) + (1 - a) mean_speed + sqrt(1 - a^2) speed_sd w   (then >= 0)
///   d_n = d_(n-1) + (1 - a) wrap(mean_dir - d_(n-1)) + sqrt(1 - a^2) dir_sd w
///   p_n likewise around mean_pitch (then clamped to [-pi/2, pi/2])
/// (the heading moves towards its mean along the shorter way round). Between
/// updates the node flies at the constant velocity
/// s (cos p cos d, cos p sin d, sin p). A face of the box reflects it
/// specularly, at the instant it reaches it, not at the next update: the
/// velocity component normal to the face changes sign, and so do the heading
/// (or pitch) and its mean, mirrored in that face, so the node is not pushed
/// back into the face it bounced off. A zero-width axis holds its coordinate
/// (velocity zero along it). At t_0 = 0: the start point, the mean speed,
/// heading and pitch. Before 0 the node is at the start point, still.
///
/// Deterministic by seed with any compiler (own generator). Updates are
/// generated lazily and cached like RandomWaypointModel's: amortised O(1) at
/// non-decreasing times.
class GaussMarkovModel final : public MobilityModel {
 public:
  /// Validates `settings`.
  explicit GaussMarkovModel(const GaussMarkovSettings& settings);
  ~GaussMarkovModel() override;
  GaussMarkovModel(GaussMarkovModel&&) noexcept;
  GaussMarkovModel& operator=(GaussMarkovModel&&) noexcept;

  MotionState state_at(double t_s) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rfsitl::position::mobility
