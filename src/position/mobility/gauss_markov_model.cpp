#include "rfsitl/position/mobility/gauss_markov_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "settings_check.hpp"
#include "step_cache.hpp"

namespace rfsitl::position::mobility {
namespace {

constexpr double kPi = std::numbers::pi;

/// The process at update n (time n * interval): where the node is and how it
/// flies until the next update (before any reflection).
struct Update {
  LocalPosition position;
  double speed_mps = 0.0;
  double heading_rad = 0.0;
  double pitch_rad = 0.0;
  double mean_heading_rad = 0.0;
  double mean_pitch_rad = 0.0;
  Velocity velocity;
};

/// One axis of a straight flight folded into [lo, hi] by specular reflection:
/// the coordinate reached and whether an odd number of faces were hit (the
/// velocity along the axis is then reversed).
struct Folded {
  double coordinate;
  bool reversed;
};

Folded fold(double x, double lo, double hi) {
  const double width = hi - lo;
  if (width <= 0.0) return {lo, false};
  // The unfolded line crosses a face every `width`: k crossings, r beyond the last.
  const double k = std::floor((x - lo) / width);
  const double r = std::clamp((x - lo) - k * width, 0.0, width);
  const bool reversed = std::fmod(std::fabs(k), 2.0) == 1.0;
  return {std::clamp(reversed ? hi - r : lo + r, lo, hi), reversed};
}

/// Into (-pi, pi].
double wrap(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

struct UpdateGenerator {
  GaussMarkovSettings s;

  Update first(detail::MobilityRandom& r) const {
    Update u;
    u.position = s.start ? *s.start
                         : s.box.clamp({r.uniform(s.box.x_min_m, s.box.x_max_m),
                                        r.uniform(s.box.y_min_m, s.box.y_max_m),
                                        r.uniform(s.box.z_min_m, s.box.z_max_m)});
    u.speed_mps = s.mean_speed_mps;
    u.heading_rad = wrap(s.mean_direction_rad);
    u.pitch_rad = s.mean_pitch_rad;
    u.mean_heading_rad = u.heading_rad;
    u.mean_pitch_rad = s.mean_pitch_rad;
    u.velocity = velocity_of(u);
    return u;
  }

  Update next(const Update& prev, detail::MobilityRandom& r) const {
    Update u = prev;
    const auto [x, flip_x] = along(prev, s.update_interval_s, 0);
    const auto [y, flip_y] = along(prev, s.update_interval_s, 1);
    const auto [z, flip_z] = along(prev, s.update_interval_s, 2);
    u.position = {x, y, z};
    // Mirror the direction and its mean in every face that was hit.
    if (flip_x) {
      u.heading_rad = wrap(kPi - u.heading_rad);
      u.mean_heading_rad = wrap(kPi - u.mean_heading_rad);
    }
    if (flip_y) {
      u.heading_rad = wrap(-u.heading_rad);
      u.mean_heading_rad = wrap(-u.mean_heading_rad);
    }
    if (flip_z) {
      u.pitch_rad = -u.pitch_rad;
      u.mean_pitch_rad = -u.mean_pitch_rad;
    }
    const double a = s.alpha;
    const double noise = std::sqrt(1.0 - a * a);
    u.speed_mps = std::max(
        0.0, a * u.speed_mps + (1.0 - a) * s.mean_speed_mps + noise * s.speed_sd_mps * r.normal());
    u.heading_rad = wrap(u.heading_rad + (1.0 - a) * wrap(u.mean_heading_rad - u.heading_rad) +
                         noise * s.direction_sd_rad * r.normal());
    u.pitch_rad = std::clamp(
        a * u.pitch_rad + (1.0 - a) * u.mean_pitch_rad + noise * s.pitch_sd_rad * r.normal(),
        -kPi / 2, kPi / 2);
    u.velocity = velocity_of(u);
    return u;
  }

  /// Axis `axis` (0 x, 1 y, 2 z) of `u`'s flight `tau` seconds after its update.
  Folded along(const Update& u, double tau, int axis) const {
    const Box& b = s.box;
    switch (axis) {
      case 0:
        return fold(u.position.x_m + u.velocity.vx_mps * tau, b.x_min_m, b.x_max_m);
      case 1:
        return fold(u.position.y_m + u.velocity.vy_mps * tau, b.y_min_m, b.y_max_m);
      default:
        return fold(u.position.z_m + u.velocity.vz_mps * tau, b.z_min_m, b.z_max_m);
    }
  }

  Velocity velocity_of(const Update& u) const {
    // A zero-width axis holds its coordinate, so it has no velocity to report.
    const double horizontal = u.speed_mps * std::cos(u.pitch_rad);
    const Box& b = s.box;
    return {b.x_max_m > b.x_min_m ? horizontal * std::cos(u.heading_rad) : 0.0,
            b.y_max_m > b.y_min_m ? horizontal * std::sin(u.heading_rad) : 0.0,
            b.z_max_m > b.z_min_m ? u.speed_mps * std::sin(u.pitch_rad) : 0.0};
  }
};

}  // namespace

void GaussMarkovSettings::validate() const {
  constexpr std::string_view kRule = "must be >= 0 and finite";
  box.validate("gauss_markov.box");
  detail::require(alpha >= 0.0 && alpha <= 1.0, "gauss_markov.alpha", "must be in [0, 1]", alpha);
  detail::require(mean_speed_mps >= 0.0 && std::isfinite(mean_speed_mps),
                  "gauss_markov.mean_speed_mps", kRule, mean_speed_mps);
  detail::require(std::isfinite(mean_direction_rad), "gauss_markov.mean_direction_rad",
                  "must be finite", mean_direction_rad);
  detail::require(mean_pitch_rad >= -kPi / 2 && mean_pitch_rad <= kPi / 2,
                  "gauss_markov.mean_pitch_rad", "must be in [-pi/2, pi/2]", mean_pitch_rad);
  detail::require(speed_sd_mps >= 0.0 && std::isfinite(speed_sd_mps), "gauss_markov.speed_sd_mps",
                  kRule, speed_sd_mps);
  detail::require(direction_sd_rad >= 0.0 && std::isfinite(direction_sd_rad),
                  "gauss_markov.direction_sd_rad", kRule, direction_sd_rad);
  detail::require(pitch_sd_rad >= 0.0 && std::isfinite(pitch_sd_rad), "gauss_markov.pitch_sd_rad",
                  kRule, pitch_sd_rad);
  detail::require(update_interval_s > 0.0 && std::isfinite(update_interval_s),
                  "gauss_markov.update_interval_s", "must be > 0 and finite", update_interval_s);
  if (start) {
    detail::require_position("gauss_markov.start", *start);
    if (!box.contains(*start)) {
      throw std::invalid_argument("gauss_markov.start must be inside gauss_markov.box");
    }
  }
}

struct GaussMarkovModel::Impl {
  detail::StepCache<Update, UpdateGenerator> updates;
  LocalPosition start = updates.at(0).position;
};

GaussMarkovModel::GaussMarkovModel(const GaussMarkovSettings& settings) {
  settings.validate();
  impl_ = std::make_unique<Impl>(Impl{{UpdateGenerator{settings}, settings.seed}});
}

GaussMarkovModel::~GaussMarkovModel() = default;
GaussMarkovModel::GaussMarkovModel(GaussMarkovModel&&) noexcept = default;
GaussMarkovModel& GaussMarkovModel::operator=(GaussMarkovModel&&) noexcept = default;

MotionState GaussMarkovModel::state_at(double t_s) {
  if (t_s < 0.0) return {impl_->start, {}};
  const UpdateGenerator& g = impl_->updates.generator();
  const double interval = g.s.update_interval_s;
  // Clamped so the conversion is defined; no run reaches 2^53 updates.
  const double n = std::min(std::floor(t_s / interval), 0x1.0p53);
  const Update& u = impl_->updates.at(static_cast<std::size_t>(n));
  const double tau = t_s - n * interval;
  const Folded x = g.along(u, tau, 0);
  const Folded y = g.along(u, tau, 1);
  const Folded z = g.along(u, tau, 2);
  return {{x.coordinate, y.coordinate, z.coordinate},
          {x.reversed ? -u.velocity.vx_mps : u.velocity.vx_mps,
           y.reversed ? -u.velocity.vy_mps : u.velocity.vy_mps,
           z.reversed ? -u.velocity.vz_mps : u.velocity.vz_mps}};
}

}  // namespace rfsitl::position::mobility
