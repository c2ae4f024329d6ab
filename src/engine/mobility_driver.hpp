#pragma once
// Internal to the engine: moves the nodes that have a mobility model, on the
// virtual clock, every engine.mobility_update_s. Engine thread only.
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::engine {

class MobilityDriver {
 public:
  /// Builds every node's model (scenario.nodes[i].mobility). Throws
  /// std::invalid_argument or std::runtime_error naming the node.
  explicit MobilityDriver(const scenario::Scenario& s);

  bool empty() const { return moving_.empty(); }

  /// Wall seconds spent in the updates that moved nodes (the clock is read
  /// only then, not every tick).
  double wall_s() const { return wall_s_; }

  /// At the first tick at or after each update time: sets every modelled node's
  /// position for the virtual time `now` (samples), and tells `velocity` each
  /// one's velocity. Returns true when it did. A node's position thus lags its
  /// model by at most one update interval.
  bool update(SampleTime now, channel::ChannelMatrix& channel,
              const std::function<void(std::size_t, const position::Velocity&)>& velocity);

 private:
  struct Moving {
    std::size_t index;
    std::unique_ptr<position::mobility::MobilityModel> model;
  };
  GeodeticPosition origin_;
  double sample_rate_hz_;
  SampleTime interval_;
  SampleTime next_ = 0;
  double wall_s_ = 0.0;
  std::vector<Moving> moving_;
};

}  // namespace rfsitl::engine
