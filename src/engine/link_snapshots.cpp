#include "link_snapshots.hpp"

#include <algorithm>

namespace rfsitl::engine {

void LinkSnapshots::maybe_copy(const channel::ChannelMatrix& channel, SampleTime now) {
  if (now < next_copy_) return;
  copy_if_stale(channel, now);
}

void LinkSnapshots::copy_if_stale(const channel::ChannelMatrix& channel, SampleTime now) {
  if (!stale_) return;
  if (channel.time_varying()) {
    copy_links(channel);
    copied(now, kLinksPeriodS);
  } else {
    copy_gains(channel);
    copied(now, kGainsPeriodS);
  }
}

void LinkSnapshots::copy_gains(const channel::ChannelMatrix& channel) {
  const std::size_t n = channel.size();
  std::vector<std::optional<Ecef>> pos(n);
  std::vector<float> gains(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    pos[i] = channel.position(i);
    for (std::size_t m = 0; m < n; ++m) gains[i * n + m] = channel.power_gain(i, m);
  }
  std::lock_guard lock(mutex_);
  positions_ = std::move(pos);
  gains_ = std::move(gains);
}

void LinkSnapshots::copy_links(const channel::ChannelMatrix& channel) {
  std::vector<std::optional<Ecef>> pos(channel.size());
  for (std::size_t i = 0; i < pos.size(); ++i) pos[i] = channel.position(i);
  // The links themselves (coefficients, responses, positions, velocities:
  // what power_gain_at reads), each dispersive link with its response.
  auto links = std::make_shared<const channel::ChannelMatrix>(channel);
  std::lock_guard lock(mutex_);
  positions_ = std::move(pos);
  links_ = std::move(links);
}

void LinkSnapshots::copied(SampleTime now, double period_s) {
  stale_ = false;
  next_copy_ = now + static_cast<SampleTime>(period_s * fs_);
}

std::vector<std::optional<Ecef>> LinkSnapshots::positions() const {
  std::lock_guard lock(mutex_);
  return positions_;
}

std::vector<float> LinkSnapshots::link_gains(SampleTime now) const {
  std::shared_ptr<const channel::ChannelMatrix> links;
  {
    std::lock_guard lock(mutex_);
    if (!links_) return gains_;
    links = links_;
  }
  const auto period = std::max<SampleTime>(1, static_cast<SampleTime>(kLinksPeriodS * fs_));
  const SampleTime at = now - now % period;
  std::lock_guard lock(faded_mutex_);
  if (links != faded_of_ || at != faded_at_) {
    const std::size_t n = links->size();
    const double t_s = static_cast<double>(at) / fs_;
    faded_.resize(n * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t m = 0; m < n; ++m) faded_[i * n + m] = links->power_gain_at(i, m, t_s);
    }
    faded_of_ = std::move(links);
    faded_at_ = at;
  }
  return faded_;
}

}  // namespace rfsitl::engine
