#pragma once
// The lazily generated steps of a seeded model (random waypoint legs, Gauss-
// Markov updates). Step k + 1 follows from step k and the generator, so a step
// is known only once all before it were drawn: the cache keeps a window of
// recent steps, extends it forward on demand and, asked for a step it has
// dropped, starts over from the seed. A run that moves forward in time pays
// amortised O(1) per step and bounded memory.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mobility_random.hpp"

namespace rfsitl::position::mobility::detail {

/// Generator: `Step first(MobilityRandom&)` and `Step next(const Step&,
/// MobilityRandom&)`, both pure functions of their arguments.
template <class Step, class Generator>
class StepCache {
 public:
  /// Steps kept behind the newest one when the window is trimmed.
  static constexpr std::size_t kWindow = 256;

  StepCache(Generator generator, std::uint64_t seed)
      : generator_(std::move(generator)), seed_(seed), random_(seed) {
    restart();
  }

  const Generator& generator() const { return generator_; }
  /// The oldest kept step's index, and one past the newest.
  std::size_t begin_index() const { return first_; }
  std::size_t end_index() const { return first_ + steps_.size(); }

  /// Step `k`, generating or regenerating what it takes. The reference lasts
  /// until the next call.
  const Step& at(std::size_t k) {
    if (k < first_) restart();
    while (k >= end_index()) extend();
    return steps_[k - first_];
  }

 private:
  void restart() {
    random_ = MobilityRandom(seed_);
    steps_.clear();
    first_ = 0;
    steps_.push_back(generator_.first(random_));
  }

  void extend() {
    steps_.push_back(generator_.next(steps_.back(), random_));
    if (steps_.size() >= 2 * kWindow) {
      // Dropping a half at a time keeps the erase amortised O(1) per step.
      steps_.erase(steps_.begin(), steps_.end() - static_cast<std::ptrdiff_t>(kWindow));
      first_ += kWindow;
    }
  }

  Generator generator_;
  std::uint64_t seed_;
  MobilityRandom random_;
  std::vector<Step> steps_;
  std::size_t first_ = 0;
};

}  // namespace rfsitl::position::mobility::detail
