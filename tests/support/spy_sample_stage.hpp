#pragma once
/// A test double for sample stages: it multiplies the samples by a factor and
/// records what it was asked (each advance() and apply()), and it says
/// whether skipping stays exact as the test wants, so that a test of the
/// channel's chain needs no real stage.
#include <mutex>
#include <vector>

#include "rfsitl/channel/sample_stage.hpp"

namespace rfsitl::testing {

class SpySampleStage final : public channel::SampleStage {
 public:
  struct Advance {
    SampleTime tick_start = 0;
    bool applies = false;
  };
  struct Apply {
    std::size_t node = 0;
    SampleTime first_sample = 0;
    std::size_t samples = 0;
  };

  explicit SpySampleStage(cf32 factor = {1.0F, 0.0F}, bool skipping_exact = true)
      : factor_(factor), skipping_exact_(skipping_exact) {}

  void advance(SampleTime tick_start, bool will_apply) override {
    advances.push_back({tick_start, will_apply});
  }

  void apply(std::size_t node, SampleTime first_sample, std::span<cf32> x) const override {
    for (cf32& v : x) v *= factor_;
    const std::lock_guard lock(mutex_);
    applies.push_back({node, first_sample, x.size()});
  }

  bool keeps_skipping_exact() const override { return skipping_exact_; }

  std::vector<Advance> advances;
  mutable std::vector<Apply> applies;  // apply() may run on several threads

 private:
  cf32 factor_;
  bool skipping_exact_;
  mutable std::mutex mutex_;
};

}  // namespace rfsitl::testing
