#include "epuck_vrep_compat/epuck/diff_drive.hpp"

#include <algorithm>
#include <cmath>

namespace evc {
namespace {

constexpr double kPi = 3.14159265358979323846;

double sinc(double a) {
  // The Taylor form below 1e-4 rad is exact to double precision (next term a^4 / 120).
  return std::abs(a) < 1e-4 ? 1.0 - a * a / 6.0 : std::sin(a) / a;
}

}  // namespace

WheelPair clamp_wheel_command(const WheelPair& command_rad_s, double max_wheel_speed_rad_s) {
  if (!std::isfinite(command_rad_s.left) || !std::isfinite(command_rad_s.right)) return {};
  const double largest = std::max(std::abs(command_rad_s.left), std::abs(command_rad_s.right));
  if (largest <= max_wheel_speed_rad_s) return command_rad_s;
  const double scale = max_wheel_speed_rad_s / largest;
  return {command_rad_s.left * scale, command_rad_s.right * scale};
}

WheelPair apply_wheel_slip(const WheelPair& speeds_rad_s, double slip_stddev, Rng& rng) {
  if (slip_stddev <= 0.0) return speeds_rad_s;
  const double left = speeds_rad_s.left * (1.0 + slip_stddev * rng.normal());
  const double right = speeds_rad_s.right * (1.0 + slip_stddev * rng.normal());
  return {left, right};
}

Twist2 body_twist(const WheelPair& speeds_rad_s, double wheel_radius_m,
                  double wheel_separation_m) {
  return {wheel_radius_m * (speeds_rad_s.right + speeds_rad_s.left) / 2.0,
          wheel_radius_m * (speeds_rad_s.right - speeds_rad_s.left) / wheel_separation_m};
}

ArcMove arc_move(double yaw_rad, const Twist2& twist, double dt_s) {
  const double half_turn = 0.5 * twist.w_rad_s * dt_s;
  const double heading = yaw_rad + half_turn;
  return {twist.v_m_s * dt_s * sinc(half_turn), std::cos(heading), std::sin(heading),
          wrap_angle(yaw_rad + 2.0 * half_turn)};
}

Pose2 integrate_arc(const Pose2& pose, const Twist2& twist, double dt_s) {
  return apply_arc(pose, arc_move(pose.yaw_rad, twist, dt_s));
}

double wrap_angle(double angle_rad) {
  // Inside (-π, π) remainder returns the angle itself, bit for bit; most calls are there.
  if (std::abs(angle_rad) < kPi) return angle_rad;
  const double wrapped = std::remainder(angle_rad, 2.0 * kPi);  // in [-π, π]
  return wrapped >= kPi ? wrapped - 2.0 * kPi : wrapped;
}

}  // namespace evc
