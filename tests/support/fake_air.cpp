#include "fake_air.hpp"

#include <algorithm>
#include <cmath>

namespace rfsitl::testing {
namespace {

std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

cf32 AirFrame::sample(std::size_t j) const {
  // Two hash bits pick the quadrant: no trigonometry per sample.
  static const float kAxis = 1.0F / std::sqrt(2.0F);
  const std::uint64_t h = splitmix64((id << 32) ^ static_cast<std::uint64_t>(j));
  return {(h & 1U) != 0 ? kAxis : -kAxis, (h & 2U) != 0 ? kAxis : -kAxis};
}

FakeAir::FakeAir(SampleTime retention_samples) : retention_(retention_samples) {}

std::shared_ptr<const AirFrame> FakeAir::add(AirFrame frame) {
  std::lock_guard lock(mutex_);
  frame.id = next_id_++;
  const SampleTime horizon = frame.start - retention_;
  std::erase_if(frames_, [&](const auto& f) { return f->end() < horizon; });
  frames_.push_back(std::make_shared<const AirFrame>(std::move(frame)));
  return frames_.back();
}

std::vector<std::shared_ptr<const AirFrame>> FakeAir::starting_in(SampleTime from, SampleTime to,
                                                                  const void* receiver) const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<const AirFrame>> found;
  for (const auto& f : frames_) {
    if (f->sender != receiver && f->start >= from && f->start < to) found.push_back(f);
  }
  return found;
}

}  // namespace rfsitl::testing
