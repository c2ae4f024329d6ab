#pragma once
/// A test double for channel stages: its gain is whatever the test's function
/// says for a link, and it counts the links it was asked about, so that a test
/// of the link budget or the channel matrix needs no real stage.
#include <atomic>
#include <complex>
#include <functional>
#include <memory>
#include <utility>

#include "rfsitl/channel/channel_stage.hpp"

namespace rfsitl::testing {

class SpyGainStage final : public channel::GainStage {
 public:
  struct Traits {
    bool reciprocal = true;
    bool time_varying = false;
    bool depends_on_attitude = false;
    double update_interval_s = 0.0;
  };
  using GainOf = std::function<std::complex<double>(const channel::LinkGeometry&)>;

  SpyGainStage(GainOf gain_of, Traits traits, std::shared_ptr<std::atomic<int>> calls)
      : gain_of_(std::move(gain_of)), traits_(traits), calls_(std::move(calls)) {}

  std::complex<double> gain(const channel::LinkGeometry& link) const override {
    calls_->fetch_add(1);
    return gain_of_(link);
  }
  bool reciprocal() const override { return traits_.reciprocal; }
  bool time_varying() const override { return traits_.time_varying; }
  bool depends_on_attitude() const override { return traits_.depends_on_attitude; }
  double update_interval_s() const override { return traits_.update_interval_s; }

 private:
  GainOf gain_of_;
  Traits traits_;
  std::shared_ptr<std::atomic<int>> calls_;
};

}  // namespace rfsitl::testing
