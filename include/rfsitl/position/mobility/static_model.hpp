#pragma once
/// A node that does not move.
#include "rfsitl/common/position.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility {

struct StaticSettings {
  Position position;  ///< local metres or WGS84 (converted once, see local_frame.hpp)

  /// Throws std::invalid_argument naming `static.position` when a coordinate is
  /// not finite or out of rfsitl/common/position_limits.hpp.
  void validate() const;
};

/// Always at the same point, velocity zero.
class StaticModel final : public MobilityModel {
 public:
  /// Validates `settings`; `origin` is the scenario origin for a WGS84 position.
  StaticModel(const StaticSettings& settings, const GeodeticPosition& origin);

  MotionState state_at(double t_s) override;

 private:
  LocalPosition position_;
};

}  // namespace rfsitl::position::mobility
