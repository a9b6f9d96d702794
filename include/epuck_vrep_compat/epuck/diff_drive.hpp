/// @file
/// Differential-drive kinematics of the e-puck: command limits, wheel slip noise and exact
/// integration of the unicycle pose.
///
/// With wheel radius r, wheel separation L and wheel speeds ω_l, ω_r (rad/s, positive forward):
///
///     v = r (ω_r + ω_l) / 2        (m/s, along body x)
///     w = r (ω_r - ω_l) / L        (rad/s, about z, counter-clockwise positive)
///
/// and over a step dt with constant (v, w), Δ = w dt, the pose moves along the exact arc
///
///     x' = x + v dt cos(θ + Δ/2) sinc(Δ/2)
///     y' = y + v dt sin(θ + Δ/2) sinc(Δ/2)       sinc(a) = sin(a) / a, sinc(0) = 1
///     θ' = θ + Δ
///
/// which equals x + v/w (sin θ' - sin θ), y - v/w (cos θ' - cos θ), stays exact as w -> 0,
/// and has no Euler error at any step length.
///
/// Slip: the wheels turn at ω (1 + σ n), n ~ N(0, 1) per wheel per step, while odometry
/// integrates the commanded ω, so odometry drifts from ground truth as real wheel odometry does.
#pragma once

#include "epuck_vrep_compat/random/rng.hpp"

namespace evc {

/// Left and right wheel values (rad/s or rad).
struct WheelPair {
  double left = 0.0;
  double right = 0.0;
};

/// A planar pose in the world frame.
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

/// Forward speed and yaw rate of the body.
struct Twist2 {
  double v_m_s = 0.0;
  double w_rad_s = 0.0;
};

/// Limits a command to ±max: when a wheel exceeds it both are scaled by the same factor, so the
/// path's curvature is kept. A non-finite command on either wheel stops both (half a command
/// would turn the robot in a direction nobody asked for).
WheelPair clamp_wheel_command(const WheelPair& command_rad_s, double max_wheel_speed_rad_s);

/// Wheel speeds after slip: each multiplied by (1 + slip_stddev N(0,1)); no draw when 0.
WheelPair apply_wheel_slip(const WheelPair& speeds_rad_s, double slip_stddev, Rng& rng);

/// (v, w) of the body for wheel speeds.
Twist2 body_twist(const WheelPair& speeds_rad_s, double wheel_radius_m,
                  double wheel_separation_m);

/// The pose after moving with a constant twist for dt, along the exact arc; yaw wrapped.
Pose2 integrate_arc(const Pose2& pose, const Twist2& twist, double dt_s);

/// What integrate_arc computes from the heading alone, not the position: the chord's length,
/// its direction's cosine and sine, and the wrapped yaw at the end. Two poses with the same
/// heading and twist (ground truth and odometry without slip) share one; applied with
/// apply_arc, it gives integrate_arc's pose bit for bit.
struct ArcMove {
  double chord_m = 0.0;
  double cos_heading = 1.0;
  double sin_heading = 0.0;
  double yaw_rad = 0.0;
};

/// The arc of integrate_arc from heading @p yaw_rad.
ArcMove arc_move(double yaw_rad, const Twist2& twist, double dt_s);

/// The pose at the end of @p move from @p pose (whose yaw the move was made for).
inline Pose2 apply_arc(const Pose2& pose, const ArcMove& move) {
  return {pose.x_m + move.chord_m * move.cos_heading, pose.y_m + move.chord_m * move.sin_heading,
          move.yaw_rad};
}

/// An angle wrapped into [-π, π).
double wrap_angle(double angle_rad);

}  // namespace evc
