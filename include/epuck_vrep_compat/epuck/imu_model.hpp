/// @file
/// The e-puck's accelerometer and gyroscope for a robot that stays on flat ground.
///
/// Accelerometer: the specific force in the body frame (x forward, y left, z up), m/s^2,
///
///     f = R(θ)^T (a + (0, 0, g)) + b_a + n_a,      n_a ~ N(0, diag(σ_a^2))
///
/// where a is the world-frame acceleration of the body (the finite difference of ground-truth
/// velocity over the step, zero when there is no previous velocity) and R(θ) the yaw rotation
/// at the instant that difference is centred on (the start of the step, as the velocities are
/// the chords of the previous step and of this one).
/// At rest it reads (0, 0, +g) + b_a. The constant per-axis bias b_a (m/s^2) stands for what
/// makes the real robot's means differ from (0, 0, g): the sensor's offset and gain error and
/// the tilt of its mounting and of the floor (the e-puck paper's Table 1: -0.053, -0.261,
/// 9.685 m/s^2 while driving straight).
///
/// Gyroscope: the body angular velocity, rad/s,  ω = (0, 0, θ') + b_g + n_g,
/// n_g ~ N(0, diag(σ_g^2)), b_g a constant per-axis bias (rad/s).
///
/// One generator per instrument; an axis whose σ is 0 draws nothing.
#pragma once

#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

/// Noise-free specific force in the body frame for a world acceleration and a yaw.
Vec3 specific_force(const Vec3& accel_world_m_s2, double yaw_rad, double gravity_m_s2);

/// Adds independent zero-mean Gaussian noise of per-axis standard deviation @p stddev.
Vec3 add_axis_noise(const Vec3& value, const Vec3& stddev, Rng& rng);

}  // namespace evc
