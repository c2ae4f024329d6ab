#include "noise_stage.hpp"

namespace rfsitl::channel {
namespace {

/// The shared noise's stream: not a receiver's index.
constexpr std::uint64_t kSharedNoiseStream = std::uint64_t{1} << 32;

}  // namespace

NoiseStage::NoiseStage(std::size_t receivers, bool shared, std::uint64_t seed, float unit_variance,
                       std::size_t tick_samples) {
  if (shared) {
    shared_.emplace(seed, kSharedNoiseStream, unit_variance);
    shared_tick_.assign(tick_samples, cf32{});
    return;
  }
  own_.reserve(receivers);
  for (std::size_t m = 0; m < receivers; ++m) own_.emplace_back(seed, m, unit_variance);
}

void NoiseStage::advance(SampleTime tick_start, bool applies) {
  tick_start_ = tick_start;
  if (shared_ && applies) shared_->fill(shared_tick_, static_cast<std::uint64_t>(tick_start));
}

void NoiseStage::apply(std::size_t node, SampleTime first_sample, std::span<cf32> x) const {
  if (!shared_) {
    own_[node].add_to(x, static_cast<std::uint64_t>(first_sample));
    return;
  }
  const auto offset = static_cast<std::size_t>(first_sample - tick_start_);
  for (std::size_t t = 0; t < x.size(); ++t) x[t] += shared_tick_[offset + t];
}

}  // namespace rfsitl::channel
