#include "rfsitl/engine/traffic_schedule.hpp"

#include <cmath>
#include <limits>

namespace rfsitl::engine {
namespace {

constexpr double kLastSample = 0x1p62;  // far beyond any run; llround stays defined
constexpr SampleTime kNever = std::numeric_limits<SampleTime>::max();

}  // namespace

TrafficSchedule::TrafficSchedule(std::vector<scenario::TrafficItem> items, double sample_rate_hz)
    : items_(std::move(items)), sample_rate_hz_(sample_rate_hz) {
  for (std::size_t i = 0; i < items_.size(); ++i) {
    if (items_[i].repeat > 0) heap_.push({time_of(i, 0), i, 0});
  }
}

SampleTime TrafficSchedule::time_of(std::size_t item, unsigned repeat) const {
  const scenario::TrafficItem& t = items_[item];
  const double samples = (t.at_s + repeat * t.interval_s) * sample_rate_hz_;
  if (!(samples >= 0.0 && samples < kLastSample)) return kNever;
  return static_cast<SampleTime>(std::llround(samples));
}

std::optional<TrafficSchedule::Frame> TrafficSchedule::pop_due(SampleTime now) {
  if (heap_.empty() || heap_.top().at > now || heap_.top().at == kNever) return std::nullopt;
  const Cursor c = heap_.top();
  heap_.pop();
  const scenario::TrafficItem& t = items_[c.item];
  if (c.repeat + 1 < t.repeat) heap_.push({time_of(c.item, c.repeat + 1), c.item, c.repeat + 1});
  return Frame{c.at, t.src, t.dst, t.size_bytes, c.repeat};
}

}  // namespace rfsitl::engine
