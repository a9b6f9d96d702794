#include "epuck_vrep_compat/sensors/ray_proximity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "world/pose_checks.hpp"

namespace evc {

RayProximityArray::RayProximityArray(const VectorXd& min_range_m, const VectorXd& max_range_m,
                                     double noise_stddev_m, std::uint64_t seed)
    : min_range_m_(min_range_m), max_range_m_(max_range_m), noise_stddev_m_(noise_stddev_m),
      rng_(seed) {
  if (min_range_m.size() != max_range_m.size()) {
    throw std::invalid_argument("min_range_m and max_range_m must have the same length");
  }
  for (Eigen::Index i = 0; i < min_range_m.size(); ++i) {
    if (!(min_range_m[i] >= 0.0 && min_range_m[i] <= max_range_m[i] &&
          max_range_m[i] <= kWorldLimit_m)) {
      throw std::invalid_argument("sensor " + std::to_string(i) +
                                  ": need 0 <= min_range_m <= max_range_m <= 1e6");
    }
  }
  if (!(noise_stddev_m >= 0.0 && std::isfinite(noise_stddev_m))) {
    throw std::invalid_argument("noise_stddev_m must be finite and >= 0");
  }
}

ProximityReadings RayProximityArray::read(const CollisionWorld& world,
                                          const std::vector<Pose>& poses,
                                          const std::vector<int>& ignore_handles, int mask) {
  const Eigen::Index count = min_range_m_.size();
  if (static_cast<Eigen::Index>(poses.size()) != count) {
    throw std::invalid_argument("poses: expected " + std::to_string(count) + " sensor poses");
  }
  if (static_cast<Eigen::Index>(ignore_handles.size()) != count) {
    throw std::invalid_argument("ignore_handles: expected " + std::to_string(count) + " handles");
  }
  std::vector<Pose> checked(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) checked[k] = checked_pose_at(poses, k, "poses");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ProximityReadings out{VectorXi::Zero(count), VectorXd::Constant(count, kInf),
                        VectorXi::Constant(count, -1), RowMatrixXd::Zero(count, 3),
                        RowMatrixXd::Zero(count, 3)};
  for (Eigen::Index i = 0; i < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const Quat& rotation = checked[k].orientation;
    const RayHit hit = world.ray_cast(checked[k].position_m, rotation * Vec3::UnitZ(),
                                      max_range_m_[i], ignore_handles[k], mask);
    const double noise_m = noise_stddev_m_ > 0.0 ? noise_stddev_m_ * rng_.normal() : 0.0;
    if (hit.handle < 0) continue;
    if (hit.distance_m < min_range_m_[i]) {
      out.distance_m[i] = -kInf;
      continue;
    }
    const double distance_m =
        std::clamp(hit.distance_m + noise_m, min_range_m_[i], max_range_m_[i]);
    out.detected[i] = 1;
    out.distance_m[i] = distance_m;
    out.handle[i] = hit.handle;
    out.point(i, 2) = distance_m;
    out.normal.row(i) = (rotation.conjugate() * hit.normal).transpose();
  }
  return out;
}

}  // namespace evc
