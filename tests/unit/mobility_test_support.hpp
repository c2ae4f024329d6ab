#pragma once
// Test helpers shared by the mobility_*_test.cpp files: position and velocity
// comparisons, and the check that a model's reported velocity is the
// derivative of its positions.
#include <gtest/gtest.h>

#include <cmath>

#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility::testing {

/// 1 mm: the accuracy the models promise against their closed forms.
inline constexpr double kMm = 1e-3;

inline ::testing::AssertionResult near(const LocalPosition& got, const LocalPosition& want,
                                       double tol = kMm) {
  const double d = std::sqrt((got.x_m - want.x_m) * (got.x_m - want.x_m) +
                             (got.y_m - want.y_m) * (got.y_m - want.y_m) +
                             (got.z_m - want.z_m) * (got.z_m - want.z_m));
  if (d <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "(" << got.x_m << ", " << got.y_m << ", " << got.z_m << ") is " << d << " m from ("
         << want.x_m << ", " << want.y_m << ", " << want.z_m << ")";
}

inline ::testing::AssertionResult near(const Velocity& got, const Velocity& want,
                                       double tol = 1e-6) {
  const double d = std::sqrt((got.vx_mps - want.vx_mps) * (got.vx_mps - want.vx_mps) +
                             (got.vy_mps - want.vy_mps) * (got.vy_mps - want.vy_mps) +
                             (got.vz_mps - want.vz_mps) * (got.vz_mps - want.vz_mps));
  if (d <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "(" << got.vx_mps << ", " << got.vy_mps << ", " << got.vz_mps << ") m/s is " << d
         << " m/s from (" << want.vx_mps << ", " << want.vy_mps << ", " << want.vz_mps << ")";
}

/// The velocity at `t` against the forward difference over `h` seconds (the
/// models' velocity is that of the motion starting at t). Evaluating at t + h
/// and then t again also checks that going back in time gives the same answer.
inline ::testing::AssertionResult velocity_is_derivative(MobilityModel& m, double t,
                                                         double h = 1e-5, double tol = 1e-3) {
  const LocalPosition ahead = m.state_at(t + h).position;
  const MotionState now = m.state_at(t);
  const Velocity fd{(ahead.x_m - now.position.x_m) / h, (ahead.y_m - now.position.y_m) / h,
                    (ahead.z_m - now.position.z_m) / h};
  auto r = near(now.velocity, fd, tol);
  if (!r) r << " (finite difference) at t = " << t;
  return r;
}

}  // namespace rfsitl::position::mobility::testing
