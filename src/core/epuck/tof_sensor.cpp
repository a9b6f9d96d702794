#include "epuck_vrep_compat/epuck/tof_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace evc {

TofSensorArray::TofSensorArray(const TofSpec& spec, std::uint64_t seed)
    : spec_(spec), seed_(seed) {
  if (!(spec.min_range_m >= 0.0 && spec.min_range_m <= spec.max_range_m &&
        spec.max_range_m <= kWorldLimit_m)) {
    throw std::invalid_argument("time-of-flight: need 0 <= min_range_m <= max_range_m <= 1e6");
  }
  if (!spec.mount_m.allFinite() || !std::isfinite(spec.pitch_rad)) {
    throw std::invalid_argument("time-of-flight: mount_m and pitch_rad must be finite");
  }
  if (!(spec.stddev_m >= 0.0 && std::isfinite(spec.stddev_m) && spec.stddev_rel >= 0.0 &&
        std::isfinite(spec.stddev_rel))) {
    throw std::invalid_argument("time-of-flight: stddev_m and stddev_rel must be finite, >= 0");
  }
}

Rng& TofSensorArray::stream(std::uint64_t robot_id) {
  auto it = streams_.find(robot_id);
  if (it == streams_.end()) {
    it = streams_.emplace(robot_id, Rng(derive_seed(seed_, robot_id, kTofStream))).first;
  }
  return it->second;
}

void TofSensorArray::reseed(std::uint64_t seed) {
  seed_ = seed;
  streams_.clear();
}

VectorXd TofSensorArray::read(const CollisionWorld& world,
                              const Eigen::Ref<const RowMatrixXd>& planar_poses,
                              const std::vector<int>& body_handles,
                              const std::vector<std::uint64_t>& robot_ids, bool noise) {
  const Eigen::Index n = planar_poses.rows();
  if (planar_poses.cols() != 3 || static_cast<Eigen::Index>(body_handles.size()) != n ||
      static_cast<Eigen::Index>(robot_ids.size()) != n) {
    throw std::invalid_argument("time-of-flight: planar_poses (N, 3), body_handles (N) and "
                                "robot_ids (N) must agree");
  }
  if (!planar_poses.allFinite()) {
    throw std::invalid_argument("time-of-flight: planar_poses must be finite");
  }
  // the axis in the body frame: +x pitched about y (positive pitch tilts +x towards -z)
  const double cp = std::cos(spec_.pitch_rad), sp = std::sin(spec_.pitch_rad);
  const Vec3 axis_body(cp, 0.0, -sp);
  VectorXd out(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = planar_poses(i, 0), y = planar_poses(i, 1), yaw = planar_poses(i, 2);
    const double c = std::cos(yaw), s = std::sin(yaw);
    const Vec3 origin(x + c * spec_.mount_m.x() - s * spec_.mount_m.y(),
                      y + s * spec_.mount_m.x() + c * spec_.mount_m.y(), spec_.mount_m.z());
    const Vec3 direction(c * axis_body.x() - s * axis_body.y(),
                         s * axis_body.x() + c * axis_body.y(), axis_body.z());
    const RayHit hit = world.ray_cast(origin, direction, spec_.max_range_m, body_handles[i]);
    const double d = hit.distance_m;
    double draw = 0.0;
    if (noise) {
      const double sd = spec_.stddev_m + spec_.stddev_rel * (std::isfinite(d) ? d : 0.0);
      draw = sd * stream(robot_ids[i]).normal();
    }
    out[i] = std::isfinite(d)
                 ? std::clamp(d + draw, spec_.min_range_m, spec_.max_range_m)
                 : spec_.max_range_m;
  }
  return out;
}

}  // namespace evc
