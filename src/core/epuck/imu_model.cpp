#include "epuck_vrep_compat/epuck/imu_model.hpp"

#include <cmath>

namespace evc {

Vec3 specific_force(const Vec3& accel_world_m_s2, double yaw_rad, double gravity_m_s2) {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  const Vec3 f = accel_world_m_s2 + Vec3(0.0, 0.0, gravity_m_s2);
  return Vec3(c * f.x() + s * f.y(), -s * f.x() + c * f.y(), f.z());
}

Vec3 add_axis_noise(const Vec3& value, const Vec3& stddev, Rng& rng) {
  Vec3 noisy = value;
  for (int axis = 0; axis < 3; ++axis) {
    if (stddev[axis] > 0.0) noisy[axis] += stddev[axis] * rng.normal();
  }
  return noisy;
}

}  // namespace evc
