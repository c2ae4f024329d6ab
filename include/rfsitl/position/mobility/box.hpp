#pragma once
/// An axis-aligned region of the local frame that a random model keeps its node in.
#include <string_view>

#include "rfsitl/common/position.hpp"

namespace rfsitl::position::mobility {

/// [x_min, x_max] x [y_min, y_max] x [z_min, z_max] in local ENU metres, closed.
/// A zero-width axis (min == max) is allowed: the node stays at that coordinate
/// (a flat box keeps a fixed altitude).
struct Box {
  double x_min_m = 0.0;
  double x_max_m = 0.0;
  double y_min_m = 0.0;
  double y_max_m = 0.0;
  double z_min_m = 0.0;
  double z_max_m = 0.0;

  bool contains(const LocalPosition& p) const;
  /// True when every axis has zero width (the box is one point).
  bool is_point() const;
  /// `p` moved to the nearest point of the box (each coordinate clamped).
  LocalPosition clamp(const LocalPosition& p) const;

  /// Throws std::invalid_argument naming the field when a corner fails the
  /// position limits ("random_waypoint.box.min: x is not a finite number
  /// (nan)") or a min exceeds its max ("random_waypoint.box.x_max_m must be
  /// >= x_min_m (got -5)").
  void validate(std::string_view field) const;
};

}  // namespace rfsitl::position::mobility
