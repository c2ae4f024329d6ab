#include "rfsitl/position/source/velocity_estimator.hpp"

#include <cmath>

namespace rfsitl::position {

Velocity VelocityEstimator::update(double t_s, const LocalPosition& p) {
  if (!last_ || t_s - last_->t_s > max_gap_s_) {
    reset();
    last_ = Fix{t_s, p};
    return velocity_;
  }
  const double dt = t_s - last_->t_s;
  if (!(dt > 0.0)) {  // a second report at the same instant replaces the first
    last_->p = p;
    return velocity_;
  }
  const Velocity raw{(p.x_m - last_->p.x_m) / dt, (p.y_m - last_->p.y_m) / dt,
                     (p.z_m - last_->p.z_m) / dt};
  const double w = have_difference_ ? 1.0 - std::exp(-dt / tau_s_) : 1.0;
  velocity_.vx_mps += w * (raw.vx_mps - velocity_.vx_mps);
  velocity_.vy_mps += w * (raw.vy_mps - velocity_.vy_mps);
  velocity_.vz_mps += w * (raw.vz_mps - velocity_.vz_mps);
  have_difference_ = true;
  last_ = Fix{t_s, p};
  return velocity_;
}

}  // namespace rfsitl::position
