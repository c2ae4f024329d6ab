#pragma once
/// For tests of channel stages: links between given ends, the
/// Kolmogorov-Smirnov test for random stages, and what a stage's declaration
/// refuses.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/channel/link_geometry.hpp"
#include "rfsitl/config/settings.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::testing {

/// Node `index` at local east/north/up metres, turned as `attitude` says.
inline channel::LinkEnd end(std::size_t index, double east_m, double north_m, double up_m,
                            std::optional<channel::Orientation> attitude = std::nullopt) {
  channel::LinkEnd e;
  e.index = index;
  e.local = {east_m, north_m, up_m};
  e.attitude = attitude;
  return e;
}

/// The link tx -> rx with its distances from the ends' local positions.
inline channel::LinkGeometry link(const channel::LinkEnd& tx, const channel::LinkEnd& rx) {
  channel::LinkGeometry g;
  g.tx = tx;
  g.rx = rx;
  g.distance_m = std::hypot(tx.local.x_m - rx.local.x_m, tx.local.y_m - rx.local.y_m,
                            tx.local.z_m - rx.local.z_m);
  g.horizontal_m = std::hypot(tx.local.x_m - rx.local.x_m, tx.local.y_m - rx.local.y_m);
  return g;
}

/// P(D_n >= d) for the Kolmogorov-Smirnov statistic of n samples, by the
/// asymptotic Kolmogorov law Q(l) = 2 sum_k (-1)^(k-1) exp(-2 k^2 l^2) with
/// Stephens' small-sample correction l = (sqrt n + 0.12 + 0.11 / sqrt n) d.
inline double kolmogorov_p_value(double d, std::size_t n) {
  const double root_n = std::sqrt(static_cast<double>(n));
  const double l = (root_n + 0.12 + 0.11 / root_n) * d;
  if (l < 0.2) return 1.0;  // the series converges slowly there; p is 1 to 1e-9
  double q = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * l * l);
    q += (k % 2 == 1 ? 2.0 : -2.0) * term;
    if (term < 1e-16) break;
  }
  return std::clamp(q, 0.0, 1.0);
}

/// sup |F_n - F| for ascending samples whose model CDF values are `cdf`.
inline double ks_statistic(const std::vector<double>& cdf) {
  const auto n = static_cast<double>(cdf.size());
  double d = 0.0;
  for (std::size_t i = 0; i < cdf.size(); ++i) {
    d = std::max({d, static_cast<double>(i + 1) / n - cdf[i], cdf[i] - static_cast<double>(i) / n});
  }
  return d;
}

/// The registered stage `type` with `settings` over its defaults, checked and
/// built as a scenario builds it (fails the test if there is no such stage).
inline std::unique_ptr<channel::GainStage> make_stage(const std::string& type,
                                                      const config::Settings& settings,
                                                      double sample_rate_hz, std::uint64_t seed) {
  const channel::ChannelStageComponent* c = channel::find_channel_stage(type);
  if (c == nullptr) throw std::invalid_argument("no stage " + type);
  config::Settings all = c->info.defaults();
  for (const auto& [key, value] : settings) all.set(key, value);
  c->info.validate(all);
  channel::StageContext context;
  context.seed = seed;
  context.sample_rate_hz = sample_rate_hz;
  return c->make(all, context);
}

/// The multipath stage's settings for `profile: taps` with these (delay_ns,
/// gain_db) taps.
inline config::Settings multipath_taps(
    std::initializer_list<std::pair<double, double>> delay_ns_gain_db) {
  config::Settings s;
  s.set("profile", config::Value(std::string("taps")));
  config::Records taps;
  for (const auto& [delay, gain] : delay_ns_gain_db) {
    config::Record r;
    r.set("delay_ns", delay);
    r.set("gain_db", gain);
    taps.push_back(r);
  }
  s.set("taps", config::Value(taps));
  return s;
}

/// The key a stage's declaration names when `key` is set to `value` on top of
/// its defaults, or "(accepted)".
inline std::string refused_key(const std::string& stage, const std::string& key,
                               const config::Value& value) {
  const channel::ChannelStageComponent* c = channel::find_channel_stage(stage);
  if (c == nullptr) return "(no stage " + stage + ")";
  config::Settings s = c->info.defaults();
  s.set(key, value);
  try {
    c->info.validate(s);
  } catch (const config::SettingError& e) {
    return e.key();
  }
  return "(accepted)";
}

}  // namespace rfsitl::testing
