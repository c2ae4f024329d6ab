#include "rfsitl/channel/channel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "rfsitl/channel/mixer.hpp"

namespace rfsitl::channel {
namespace {

/// The noise stream of shared_noise: not a receiver's index.
constexpr std::uint64_t kSharedNoiseStream = std::uint64_t{1} << 32;

}  // namespace

Channel::Channel(std::size_t nodes, std::shared_ptr<const LinkBudget> budget,
                 const GeodeticPosition& origin, const ChannelConfig& config)
    : matrix_(nodes, std::move(budget), origin),
      config_(config),
      gain_(1.0 / std::sqrt(config.noise_variance > 0.0 ? config.noise_variance : 1e-12)),
      // Aligned to absolute sample times, so that a coefficient is the same
      // whatever the tick size.
      grid_samples_(matrix_.time_varying()
                        ? std::max<SampleTime>(
                              1, std::llround(matrix_.update_interval_s() * config.sample_rate_hz))
                        : 0),
      noise_(nodes) {
  if (config.tick_samples == 0) throw std::invalid_argument("Channel: tick_samples must be > 0");
  if (config.noise_variance <= 0.0) return;
  const auto unit = static_cast<float>(config.noise_variance * gain_ * gain_);
  if (config.shared_noise) {
    shared_noise_.emplace(config.seed, kSharedNoiseStream, unit);
    shared_noise_buf_.assign(config.tick_samples, cf32{});
  } else {
    for (std::size_t i = 0; i < nodes; ++i) noise_[i].emplace(config.seed, i, unit);
  }
}

void Channel::begin_tick(SampleTime tick_start, bool receivers_run) {
  if (shared_noise_ && receivers_run) shared_noise_->fill(shared_noise_buf_, tick_start);
}

void Channel::receive(std::size_t m, std::span<const Transmission> active, SampleTime tick_start,
                      std::size_t first, std::span<cf32> y, Scratch& s) const {
  if (grid_samples_ > 0) {
    mix_fading(m, active, tick_start, first, y, s);
  } else {
    s.inputs.clear();
    s.coeffs.clear();
    const auto row = matrix_.receiver_row(m);
    const auto g = static_cast<float>(gain_);
    for (const Transmission& tx : active) {
      if (tx.node != m && row[tx.node] != cf32{}) {
        s.inputs.push_back(tx.samples + first);
        s.coeffs.push_back(row[tx.node] * g);
      }
    }
    mix(s.inputs, s.coeffs, y);
  }
  if (const auto& noise = noise_[m]) {
    noise->add_to(y, static_cast<std::uint64_t>(tick_start) + first);
  } else if (shared_noise_) {
    for (std::size_t t = 0; t < y.size(); ++t) y[t] += shared_noise_buf_[first + t];
  }
}

/// Time-varying coefficients: computed on the grid (absolute sample times,
/// every grid_samples_) and ramped linearly between grid points, segment by
/// segment of the tick.
void Channel::mix_fading(std::size_t m, std::span<const Transmission> active, SampleTime tick_start,
                         std::size_t first, std::span<cf32> y, Scratch& s) const {
  const double fs = config_.sample_rate_hz;
  const auto g = static_cast<float>(gain_);
  const auto at = [&](std::size_t k, SampleTime t) {
    return matrix_.coefficient_at(active[k].node, m, static_cast<double>(t) / fs) * g;
  };
  s.links.clear();
  const auto row = matrix_.receiver_row(m);
  for (std::size_t k = 0; k < active.size(); ++k) {
    if (active[k].node != m && row[active[k].node] != cf32{}) s.links.push_back(k);
  }
  std::fill(y.begin(), y.end(), cf32{});
  if (s.links.empty()) return;
  const std::size_t links = s.links.size();
  const SampleTime start = tick_start + static_cast<SampleTime>(first);
  const SampleTime end = start + static_cast<SampleTime>(y.size());
  const SampleTime u = grid_samples_;
  SampleTime g0 = start - start % u;
  s.at_next.resize(links);
  s.ramp_start.resize(links);
  s.ramp_step.resize(links);
  s.inputs.resize(links);
  std::vector<cf32>& at_g0 = s.coeffs;  // the grid point a segment starts from
  at_g0.resize(links);
  for (std::size_t j = 0; j < links; ++j) at_g0[j] = at(s.links[j], g0);
  const float inv_u = 1.0F / static_cast<float>(u);
  for (; g0 < end; g0 += u) {
    const SampleTime s0 = std::max(g0, start);
    const SampleTime s1 = std::min(g0 + u, end);
    for (std::size_t j = 0; j < links; ++j) {
      s.at_next[j] = at(s.links[j], g0 + u);
      s.ramp_step[j] = (s.at_next[j] - at_g0[j]) * inv_u;
      s.ramp_start[j] = at_g0[j] + s.ramp_step[j] * static_cast<float>(s0 - g0);
      s.inputs[j] = active[s.links[j]].samples + (s0 - tick_start);
    }
    mix_ramped_add(
        s.inputs, s.ramp_start, s.ramp_step,
        y.subspan(static_cast<std::size_t>(s0 - start), static_cast<std::size_t>(s1 - s0)));
    std::swap(at_g0, s.at_next);
  }
}

}  // namespace rfsitl::channel
