#include "rfsitl/channel/channel_matrix.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "rfsitl/channel/fractional_delay.hpp"
#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::channel {

ChannelMatrix::ChannelMatrix(std::size_t num_nodes, std::shared_ptr<const LinkBudget> budget,
                             const GeodeticPosition& origin, double sample_rate_hz)
    : n_(num_nodes),
      budget_(std::move(budget)),
      origin_(origin),
      positions_(num_nodes),
      local_(num_nodes),
      velocity_(num_nodes),
      attitude_(num_nodes),
      stamp_s_(num_nodes, 0.0),
      coeff_(num_nodes * num_nodes, cf32{0.0f, 0.0f}),
      sample_rate_hz_(sample_rate_hz) {
  if (!budget_) {
    throw std::invalid_argument("ChannelMatrix: link budget must not be null");
  }
  if (budget_->dispersive()) responses_.resize(num_nodes * num_nodes);
}

void ChannelMatrix::set_position(std::size_t i, std::optional<Ecef> pos) {
  // Not a hot path (a location feed updates a few times a second), so the
  // index is checked: a bad node index must not corrupt another node's links.
  positions_.at(i) = pos;
  if (pos) local_[i] = ecef_to_local(*pos, origin_);
  stamp_s_[i] = clock_s_;
  recompute(i);
}

std::optional<double> ChannelMatrix::distance(std::size_t a, std::size_t b) const {
  const auto& pa = positions_.at(a);
  const auto& pb = positions_.at(b);
  if (!pa || !pb) {
    return std::nullopt;
  }
  return distance_m(*pa, *pb);
}

LinkGeometry ChannelMatrix::geometry(std::size_t tx, std::size_t rx) const {
  LinkGeometry g;
  g.tx = {tx, *positions_[tx], local_[tx], velocity_[tx], attitude_[tx]};
  g.rx = {rx, *positions_[rx], local_[rx], velocity_[rx], attitude_[rx]};
  g.time_s = clock_s_;
  // The diagonal is at exactly d = 0 (the node hears itself), not whatever
  // rounding distance_m(p, p) might produce.
  if (tx != rx) {
    g.distance_m = distance_m(g.tx.ecef, g.rx.ecef);
    g.horizontal_m = std::hypot(g.tx.local.x_m - g.rx.local.x_m, g.tx.local.y_m - g.rx.local.y_m);
  }
  return g;
}

void ChannelMatrix::set_attitude(std::size_t i, const std::optional<Orientation>& a) {
  const bool changed =
      attitude_.at(i).has_value() != a.has_value() ||
      (a && (attitude_[i]->roll_rad != a->roll_rad || attitude_[i]->pitch_rad != a->pitch_rad ||
             attitude_[i]->yaw_rad != a->yaw_rad));
  attitude_[i] = a;
  if (changed && budget_->depends_on_attitude()) recompute(i);
}

cf32 ChannelMatrix::coefficient_at(std::size_t tx, std::size_t rx, double t_s) const {
  const cf32 c = coefficient(tx, rx);
  if (!time_varying() || c == cf32{}) return c;
  const std::complex<double> h = fading_at(tx, rx, t_s, 0);
  return c * cf32{static_cast<float>(h.real()), static_cast<float>(h.imag())};
}

std::complex<double> ChannelMatrix::fading_at(std::size_t tx, std::size_t rx, double t_s,
                                              std::size_t path) const {
  std::complex<double> h = 1.0;
  fading_at(tx, rx, t_s, path, std::span(&h, 1));
  return h;
}

void ChannelMatrix::fading_at(std::size_t tx, std::size_t rx, double t_s, std::size_t first_path,
                              std::span<std::complex<double>> out) const {
  if (!time_varying()) {
    std::fill(out.begin(), out.end(), std::complex<double>(1.0));
    return;
  }
  LinkGeometry g = geometry(tx, rx);
  g.time_s = t_s;
  // Only `local` moves: the time-varying stages read nothing else.
  for (LinkEnd* end : {&g.tx, &g.rx}) {
    const double dt = t_s - stamp_s_[end->index];
    end->local.x_m += end->velocity.east_mps * dt;
    end->local.y_m += end->velocity.north_mps * dt;
    end->local.z_m += end->velocity.up_mps * dt;
  }
  for (std::size_t p = 0; p < out.size(); ++p) {
    g.path = first_path + p;
    out[p] = budget_->fading(g);
  }
}

float ChannelMatrix::power_gain_at(std::size_t tx, std::size_t rx, double t_s) const {
  if (!time_varying()) return power_gain(tx, rx);
  if (dispersive()) {
    // A link without paths (the diagonal, or an end without a position) falls
    // through to its coefficient: zero, or the node hearing itself.
    const LinkResponse& r = response(tx, rx);
    if (!r.path_gains.empty()) {
      std::vector<std::complex<double>> h(r.path_gains.size());
      fading_at(tx, rx, t_s, 0, h);
      double total = 0.0;
      for (std::size_t p = 0; p < h.size(); ++p) {
        total += std::norm(std::complex<double>(r.path_gains[p]) * h[p]);
      }
      return static_cast<float>(total) * band_gain(tx, rx);
    }
  }
  return std::norm(coefficient_at(tx, rx, t_s)) * band_gain(tx, rx);
}

void ChannelMatrix::set_band_gain(std::size_t tx, std::size_t rx, float kappa) {
  if (band_gain_.empty()) band_gain_.assign(n_ * n_, 1.0F);
  band_gain_.at(rx * n_ + tx) = kappa;
}

void ChannelMatrix::recompute(std::size_t i) {
  const bool known = positions_[i].has_value();
  for (std::size_t j = 0; j < n_; ++j) {
    if (!known || !positions_[j]) {
      coeff_[i * n_ + j] = coeff_[j * n_ + i] = cf32{0.0f, 0.0f};
      continue;
    }
    // Row i: i receives from j; column i: i transmits to j. A reciprocal
    // budget fills both with one evaluation.
    const cf32 from_j = budget_->coefficient(geometry(j, i));
    coeff_[i * n_ + j] = from_j;
    coeff_[j * n_ + i] = budget_->reciprocal() ? from_j : budget_->coefficient(geometry(i, j));
  }
  if (!dispersive()) return;
  for (std::size_t j = 0; j < n_; ++j) {
    recompute_response(j, i);
    if (j != i) recompute_response(i, j);
  }
}

void ChannelMatrix::recompute_response(std::size_t tx, std::size_t rx) {
  LinkResponse& r = responses_[rx * n_ + tx];
  r.lags.clear();
  r.taps.clear();
  r.path_gains.clear();
  r.path_filters.clear();
  if (tx == rx || !positions_[tx] || !positions_[rx]) return;
  budget_->paths(geometry(tx, rx), paths_scratch_);
  std::vector<FractionalDelay> filters;
  filters.reserve(paths_scratch_.size());
  for (const Path& p : paths_scratch_) {
    filters.push_back(fractional_delay(p.delay_s * sample_rate_hz_));
    const FractionalDelay& f = filters.back();
    for (std::uint32_t l = 0; l < f.count; ++l) r.lags.push_back(f.first_lag + l);
  }
  std::sort(r.lags.begin(), r.lags.end());
  r.lags.erase(std::unique(r.lags.begin(), r.lags.end()), r.lags.end());
  const std::size_t k = r.lags.size();
  r.taps.assign(k, cf32{});
  r.path_filters.assign(paths_scratch_.size() * k, 0.0F);
  for (std::size_t p = 0; p < paths_scratch_.size(); ++p) {
    const std::complex<double> g = paths_scratch_[p].gain;
    r.path_gains.emplace_back(static_cast<float>(g.real()), static_cast<float>(g.imag()));
    const FractionalDelay& f = filters[p];
    // The filter's lags are consecutive, so they are a run of r.lags.
    const auto at = static_cast<std::size_t>(
        std::lower_bound(r.lags.begin(), r.lags.end(), f.first_lag) - r.lags.begin());
    for (std::uint32_t l = 0; l < f.count; ++l) {
      r.path_filters[p * k + at + l] = f.taps[l];
      r.taps[at + l] += r.path_gains.back() * f.taps[l];
    }
  }
  if (k > 0) max_lag_ = std::max(max_lag_, r.lags.back());
}

}  // namespace rfsitl::channel
