#pragma once
/// What a channel stage knows of one link: where its two ends are. (How they
/// move and point joins as the stages that need it arrive.)
#include <cstddef>

#include "rfsitl/common/position.hpp"

namespace rfsitl::channel {

/// One end of a link.
struct LinkEnd {
  std::size_t index = 0;  ///< the node's index, 0..N-1
  Ecef ecef;
  /// East, north, up metres around the scenario's channel.origin. Models with a
  /// ground (two-ray, TR 36.777) take up = 0, the origin's altitude, as the ground.
  LocalPosition local;
};

/// The link from `tx` to `rx`.
struct LinkGeometry {
  LinkEnd tx;
  LinkEnd rx;
  double distance_m = 0.0;    ///< straight line in ECEF, >= 0 (exactly 0 on the diagonal)
  double horizontal_m = 0.0;  ///< in the local east-north plane, >= 0
};

}  // namespace rfsitl::channel
