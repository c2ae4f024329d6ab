#include "rfsitl/channel/channel.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "noise_stage.hpp"
#include "rfsitl/channel/frequency_shift.hpp"
#include "rfsitl/channel/mixer.hpp"
#include "rfsitl/channel/noise_source.hpp"

namespace rfsitl::channel {
namespace {

/// signal_end_ of a node that never transmitted.
constexpr SampleTime kNever = std::numeric_limits<SampleTime>::min() / 2;

/// The leakage noise's streams under the run's seed: receiver m's is
/// kLeakageStreams + m, apart from the receivers' own noise (stream m).
constexpr std::uint64_t kLeakageStreams = std::uint64_t{1} << 63;

cf32 to_cf32(std::complex<double> v) {
  return {static_cast<float>(v.real()), static_cast<float>(v.imag())};
}

}  // namespace

Channel::Channel(std::size_t nodes, std::shared_ptr<const LinkBudget> budget,
                 const GeodeticPosition& origin, const ChannelConfig& config, SampleChain transmit,
                 SampleChain receive)
    : matrix_(nodes, std::move(budget), origin, config.sample_rate_hz),
      config_(config),
      gain_(1.0 / std::sqrt(config.noise_variance > 0.0 ? config.noise_variance : 1e-12)),
      // Aligned to absolute sample times, so that a coefficient is the same
      // whatever the tick size.
      grid_samples_(matrix_.time_varying()
                        ? std::max<SampleTime>(
                              1, std::llround(matrix_.update_interval_s() * config.sample_rate_hz))
                        : 0),
      transmit_(std::move(transmit)) {
  if (config.tick_samples == 0) throw std::invalid_argument("Channel: tick_samples must be > 0");
  if (matrix_.dispersive()) {
    history_.assign(nodes, std::vector<cf32>(config.tick_samples, cf32{}));
    signal_end_.assign(nodes, kNever);
  }
  if (!transmit_.empty()) staged_.assign(nodes, std::vector<cf32>(config.tick_samples));
  if (config.noise_variance > 0.0) {
    const auto unit = static_cast<float>(config.noise_variance * gain_ * gain_);
    receive_.push_back(std::make_unique<NoiseStage>(nodes, config.shared_noise, config.seed, unit,
                                                    config.tick_samples));
  }
  for (auto& stage : receive) {
    skipping_exact_ = skipping_exact_ && stage->keeps_skipping_exact();
    receive_.push_back(std::move(stage));
  }
}

void Channel::on_air(SampleTime tick_start, std::span<const Transmission> active) {
  tick_start_ = tick_start;
  if (!transmit_.empty()) {
    for (const auto& stage : transmit_) stage->advance(tick_start, !active.empty());
    staged_active_.clear();
    for (const Transmission& t : active) {
      std::vector<cf32>& x = staged_[t.node];
      std::copy_n(t.samples, x.size(), x.begin());
      for (const auto& stage : transmit_) stage->apply(t.node, tick_start, x);
      staged_active_.push_back({t.node, x.data()});
    }
    active = staged_active_;
  }
  if (!tunings_.empty()) active = shift_transmitters(tick_start, active);
  active_ = active;
  if (matrix_.dispersive()) keep_history(tick_start, active);
}

void Channel::tune(std::size_t node, const RadioTuning& tuning) {
  const std::size_t n = matrix_.size();
  if (tunings_.empty()) {
    RadioTuning shared;
    shared.tx_hz = shared.rx_hz = config_.carrier_hz;
    shared.bandwidth_hz = config_.sample_rate_hz;
    tunings_.assign(n, shared);
    tx_cycles_.assign(n, 0.0);
    rx_cycles_.assign(n, 0.0);
    bands_.assign(n * n, LinkBand{});
    shifted_.assign(n, std::vector<cf32>(config_.tick_samples));
    tx_power_.assign(n, 0.0F);
  }
  tunings_.at(node) = tuning;
  tx_cycles_[node] = (tuning.tx_hz - config_.carrier_hz) / config_.sample_rate_hz;
  rx_cycles_[node] = (tuning.rx_hz - config_.carrier_hz) / config_.sample_rate_hz;
  for (std::size_t other = 0; other < n; ++other) {
    if (other == node) continue;  // a node never mixes its own signal
    for (const auto& [tx, rx] : {std::pair{node, other}, std::pair{other, node}}) {
      const LinkBand b = link_band(tunings_[tx], tunings_[rx], config_.sample_rate_hz);
      bands_[rx * n + tx] = b;
      matrix_.set_band_gain(tx, rx, b.kappa);
    }
  }
}

std::span<const Transmission> Channel::shift_transmitters(SampleTime tick_start,
                                                          std::span<const Transmission> active) {
  shifted_active_.clear();
  for (const Transmission& t : active) {
    float power = 0.0F;
    for (std::size_t k = 0; k < config_.tick_samples; ++k) power += std::norm(t.samples[k]);
    tx_power_[t.node] = power / static_cast<float>(config_.tick_samples);
    if (tx_cycles_[t.node] == 0.0) {
      shifted_active_.push_back(t);
      continue;
    }
    std::vector<cf32>& x = shifted_[t.node];
    std::copy_n(t.samples, x.size(), x.begin());
    shift_frequency(x, tx_cycles_[t.node], static_cast<std::uint64_t>(tick_start));
    shifted_active_.push_back({t.node, x.data()});
  }
  return shifted_active_;
}

/// The leaked powers of every transmitter add into one noise variance: the
/// sum of independent Gaussians is one Gaussian. Its mean over the tick (a
/// frame that ends mid-tick leaks its average).
void Channel::arrive_in_band(std::size_t m, std::size_t first, std::span<cf32> y) const {
  const SampleTime from = tick_start_ + static_cast<SampleTime>(first);
  shift_frequency(y, -rx_cycles_[m], static_cast<std::uint64_t>(from));
  const std::size_t n = tunings_.size();
  double leaked = 0.0;
  for (const Transmission& t : active_) {
    if (t.node == m) {  // a full-duplex node hears itself through its duplexer
      leaked += tunings_[m].self_gain * tx_power_[m];
      continue;
    }
    const LinkBand& b = bands_[m * n + t.node];
    if (b.relation != BandRelation::kLeaking) continue;
    leaked += static_cast<double>(b.kappa) * std::norm(matrix_.coefficient(t.node, m)) *
              tx_power_[t.node];
  }
  if (leaked > 0.0) {
    const auto variance = static_cast<float>(leaked * gain_ * gain_);
    NoiseSource(config_.seed, kLeakageStreams + m, variance)
        .add_to(y, static_cast<std::uint64_t>(from));
  }
}

/// Shifts every transmitter's history by one tick and appends this tick's
/// samples (zeros if it is silent). A node silent for longer than the history
/// holds only zeros and is left alone.
void Channel::keep_history(SampleTime tick_start, std::span<const Transmission> active) {
  const std::size_t b = config_.tick_samples;
  if (matrix_.max_lag() > history_len_) {
    // A link got longer than any before: older samples are zeros (they were
    // never needed), so the histories grow at their front.
    const std::size_t grow = matrix_.max_lag() - history_len_;
    for (auto& h : history_) h.insert(h.begin(), grow, cf32{});
    history_len_ = matrix_.max_lag();
  }
  std::vector<const cf32*>& now = transmitting_;
  now.assign(history_.size(), nullptr);
  for (const Transmission& t : active) now.at(t.node) = t.samples;
  audible_.clear();
  const SampleTime oldest = tick_start - static_cast<SampleTime>(history_len_);
  for (std::size_t n = 0; n < history_.size(); ++n) {
    if (now[n] == nullptr && signal_end_[n] <= oldest) continue;  // all zeros already
    std::vector<cf32>& h = history_[n];
    std::memmove(h.data(), h.data() + b, history_len_ * sizeof(cf32));
    if (now[n] != nullptr) {
      std::copy_n(now[n], b, h.begin() + static_cast<std::ptrdiff_t>(history_len_));
      signal_end_[n] = tick_start + static_cast<SampleTime>(b);
    } else {
      std::fill(h.begin() + static_cast<std::ptrdiff_t>(history_len_), h.end(), cf32{});
    }
    if (signal_end_[n] > oldest) audible_.push_back(n);
  }
}

void Channel::begin_tick(SampleTime tick_start, bool receivers_run) {
  for (const auto& stage : receive_) stage->advance(tick_start, receivers_run);
}

bool Channel::tail_reaches(std::size_t n, std::size_t m, SampleTime from) const {
  const LinkResponse& r = matrix_.response(n, m);
  return !r.lags.empty() && signal_end_[n] + static_cast<SampleTime>(r.lags.back()) > from;
}

bool Channel::hears_signal(std::size_t m) const {
  if (!matrix_.dispersive()) {
    return std::any_of(active_.begin(), active_.end(), [&](const Transmission& t) {
      return t.node != m && reaches(t.node, m) && matrix_.coefficient(t.node, m) != cf32{};
    });
  }
  return std::any_of(audible_.begin(), audible_.end(), [&](std::size_t n) {
    return n != m && reaches(n, m) && matrix_.coefficient(n, m) != cf32{} &&
           tail_reaches(n, m, tick_start_);
  });
}

void Channel::receive(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const {
  if (matrix_.dispersive()) {
    const bool fading = grid_samples_ > 0;
    gather_lags(m, first, !fading, s);
    if (fading) {
      mix_fading_dispersive(m, first, y, s);
    } else {
      mix(s.inputs, s.coeffs, y);
    }
  } else if (grid_samples_ > 0) {
    mix_fading(m, first, y, s);
  } else {
    mix_flat(m, first, y, s);
  }
  finish(m, first, y);
}

void Channel::finish(std::size_t m, std::size_t first, std::span<cf32> y) const {
  if (!tunings_.empty()) arrive_in_band(m, first, y);
  const SampleTime from = tick_start_ + static_cast<SampleTime>(first);
  for (const auto& stage : receive_) stage->apply(m, from, y);
}

bool Channel::mixes_together(std::size_t min_inputs) const {
  return !matrix_.dispersive() && grid_samples_ == 0 && active_.size() >= min_inputs;
}

void Channel::receive_together(std::span<const std::size_t> ms, std::span<cf32* const> ys,
                               Scratch& s) const {
  assert(ms.size() == ys.size() && ms.size() <= kMaxTogether);
  // One row of coefficients per receiver over every active transmitter, zero
  // for itself and for unknown links: mix_rows leaves out inputs zero for all.
  s.inputs.clear();
  s.coeffs.clear();
  for (const Transmission& tx : active_) s.inputs.push_back(tx.samples);
  const auto g = static_cast<float>(gain_);
  for (const std::size_t m : ms) {
    const auto row = matrix_.receiver_row(m);
    for (const Transmission& tx : active_)
      s.coeffs.push_back(tx.node == m || !in_band(tx.node, m) ? cf32{} : row[tx.node] * g);
  }
  mix_rows(s.inputs, s.coeffs, ys, config_.tick_samples);
  for (std::size_t j = 0; j < ms.size(); ++j) finish(ms[j], 0, {ys[j], config_.tick_samples});
}

void Channel::mix_flat(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const {
  s.inputs.clear();
  s.coeffs.clear();
  const auto row = matrix_.receiver_row(m);
  const auto g = static_cast<float>(gain_);
  for (const Transmission& tx : active_) {
    if (tx.node != m && row[tx.node] != cf32{} && in_band(tx.node, m)) {
      s.inputs.push_back(tx.samples + first);
      s.coeffs.push_back(row[tx.node] * g);
    }
  }
  mix(s.inputs, s.coeffs, y);
}

/// The dispersive links that reach m in this tick, one input per lag of their
/// responses: s.links (the transmitters), s.bases (each lag's samples at the
/// tick's first sample), and `with_taps` (the static case) s.inputs and s.coeffs.
void Channel::gather_lags(std::size_t m, std::size_t first, bool with_taps, Scratch& s) const {
  s.links.clear();
  s.bases.clear();
  s.inputs.clear();
  s.coeffs.clear();
  const auto g = static_cast<float>(gain_);
  const SampleTime from = tick_start_ + static_cast<SampleTime>(first);
  for (const std::size_t n : audible_) {
    if (n == m || matrix_.coefficient(n, m) == cf32{} || !in_band(n, m) ||
        !tail_reaches(n, m, from)) {
      continue;
    }
    const LinkResponse& r = matrix_.response(n, m);
    s.links.push_back(n);
    const cf32* now = history_[n].data() + history_len_;
    for (std::size_t k = 0; k < r.lags.size(); ++k) {
      s.bases.push_back(now - r.lags[k]);
      if (!with_taps) continue;  // mix_ramped computes its coefficients itself
      s.inputs.push_back(now - r.lags[k] + first);
      s.coeffs.push_back(r.taps[k] * g);
    }
  }
}

/// Time-varying coefficients: computed on the grid (absolute sample times,
/// every grid_samples_) and ramped linearly between grid points, segment by
/// segment of the tick.
template <typename FillAt>
void Channel::mix_ramped(std::size_t first, std::span<cf32> y, Scratch& s,
                         const FillAt& fill_at) const {
  std::fill(y.begin(), y.end(), cf32{});
  const std::size_t inputs = s.bases.size();
  if (inputs == 0) return;
  const SampleTime start = tick_start_ + static_cast<SampleTime>(first);
  const SampleTime end = start + static_cast<SampleTime>(y.size());
  const SampleTime u = grid_samples_;
  SampleTime g0 = start - start % u;
  s.at_next.resize(inputs);
  s.ramp_start.resize(inputs);
  s.ramp_step.resize(inputs);
  s.inputs.resize(inputs);
  std::vector<cf32>& at_g0 = s.coeffs;  // the grid point a segment starts from
  at_g0.resize(inputs);
  fill_at(g0, at_g0);
  const float inv_u = 1.0F / static_cast<float>(u);
  for (; g0 < end; g0 += u) {
    const SampleTime s0 = std::max(g0, start);
    const SampleTime s1 = std::min(g0 + u, end);
    fill_at(g0 + u, s.at_next);
    for (std::size_t j = 0; j < inputs; ++j) {
      s.ramp_step[j] = (s.at_next[j] - at_g0[j]) * inv_u;
      s.ramp_start[j] = at_g0[j] + s.ramp_step[j] * static_cast<float>(s0 - g0);
      s.inputs[j] = s.bases[j] + (s0 - tick_start_);
    }
    mix_ramped_add(
        s.inputs, s.ramp_start, s.ramp_step,
        y.subspan(static_cast<std::size_t>(s0 - start), static_cast<std::size_t>(s1 - s0)));
    std::swap(at_g0, s.at_next);
  }
}

void Channel::mix_fading(std::size_t m, std::size_t first, std::span<cf32> y, Scratch& s) const {
  const double fs = config_.sample_rate_hz;
  const auto g = static_cast<float>(gain_);
  s.links.clear();
  s.bases.clear();
  const auto row = matrix_.receiver_row(m);
  for (const Transmission& tx : active_) {
    if (tx.node != m && row[tx.node] != cf32{} && in_band(tx.node, m)) {
      s.links.push_back(tx.node);
      s.bases.push_back(tx.samples);
    }
  }
  mix_ramped(first, y, s, [&](SampleTime t, std::vector<cf32>& out) {
    for (std::size_t j = 0; j < s.links.size(); ++j) {
      out[j] = matrix_.coefficient_at(s.links[j], m, static_cast<double>(t) / fs) * g;
    }
  });
}

/// Each path fades on its own (LinkGeometry::path); a lag's tap at a grid
/// point is the sum over paths of gain x fading x the path's filter at that lag.
void Channel::mix_fading_dispersive(std::size_t m, std::size_t first, std::span<cf32> y,
                                    Scratch& s) const {
  const double fs = config_.sample_rate_hz;
  const double g = gain_;
  mix_ramped(first, y, s, [&](SampleTime t, std::vector<cf32>& out) {
    std::size_t at = 0;
    for (const std::size_t n : s.links) {
      const LinkResponse& r = matrix_.response(n, m);
      const std::size_t lags = r.lags.size();
      s.path_fading.resize(r.path_gains.size());
      matrix_.fading_at(n, m, static_cast<double>(t) / fs, 0, s.path_fading);
      s.path_factor.resize(r.path_gains.size());
      for (std::size_t p = 0; p < r.path_gains.size(); ++p) {
        s.path_factor[p] = r.path_gains[p] * to_cf32(g * s.path_fading[p]);
      }
      for (std::size_t k = 0; k < lags; ++k) {
        cf32 tap{};
        for (std::size_t p = 0; p < r.path_gains.size(); ++p) {
          tap += s.path_factor[p] * r.path_filters[p * lags + k];
        }
        out[at + k] = tap;
      }
      at += lags;
    }
  });
}

}  // namespace rfsitl::channel
