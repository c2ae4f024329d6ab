#pragma once
/// The scenario's `traffic:` items as frames in time order, made one at a time
/// when they fall due, so that `repeat: 20000000` costs one heap entry instead
/// of twenty million queued frames. Engine thread only.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <queue>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::engine {

class TrafficSchedule {
 public:
  /// One injected frame.
  struct Frame {
    SampleTime at;  ///< first sample at which it may enter its node's queue
    NodeId src;
    NodeId dst;
    std::size_t size;
    unsigned repeat_index;  ///< 0 for an item's first frame
  };

  /// Times are at_s + r * interval_s seconds, rounded to the nearest sample
  /// at `sample_rate_hz`; a time beyond 2^62 samples never falls due
  /// (validated scenarios have none).
  TrafficSchedule(std::vector<scenario::TrafficItem> items, double sample_rate_hz);

  /// The next frame due at or before `now`, removed from the schedule; frames
  /// come in time order, ties in item order and then repeat order.
  std::optional<Frame> pop_due(SampleTime now);

 private:
  struct Cursor {
    SampleTime at;
    std::size_t item;
    unsigned repeat;
  };
  struct Later {
    bool operator()(const Cursor& a, const Cursor& b) const {
      if (a.at != b.at) return a.at > b.at;
      if (a.item != b.item) return a.item > b.item;
      return a.repeat > b.repeat;
    }
  };

  SampleTime time_of(std::size_t item, unsigned repeat) const;

  std::vector<scenario::TrafficItem> items_;
  double sample_rate_hz_;
  std::priority_queue<Cursor, std::vector<Cursor>, Later> heap_;
};

}  // namespace rfsitl::engine
