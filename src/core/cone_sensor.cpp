#include "epuck_vrep_compat/cone_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "body.hpp"
#include "epuck_vrep_compat/collision_world.hpp"

namespace evc {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

void validate_cone_sensor(const ConeSensor& sensor) {
  if (!sensor.position_m.allFinite() || !std::isfinite(sensor.yaw_rad) ||
      !std::isfinite(sensor.pitch_rad)) {
    throw std::invalid_argument("sensor position, yaw_rad and pitch_rad must be finite");
  }
  if (!(sensor.half_angle_rad >= 0.0 && sensor.half_angle_rad < 0.5 * kPi)) {
    throw std::invalid_argument("half_angle_rad must be in [0, pi/2)");
  }
  if (!(sensor.min_range_m >= 0.0 && sensor.min_range_m < sensor.max_range_m &&
        std::isfinite(sensor.max_range_m))) {
    throw std::invalid_argument("need 0 <= min_range_m < max_range_m, both finite");
  }
  if (sensor.rings < 0) throw std::invalid_argument("rings must be >= 0");
  if (sensor.azimuths < 2 || sensor.azimuths % 2 != 0) {
    throw std::invalid_argument("azimuths must be even and >= 2 (0 and pi are sampled)");
  }
}

Quat sensor_orientation(const ConeSensor& sensor) {
  return Quat(Eigen::AngleAxisd(sensor.yaw_rad, Vec3::UnitZ()) *
              Eigen::AngleAxisd(sensor.pitch_rad, Vec3::UnitY()));
}

std::vector<Vec3> cone_ray_directions(const ConeSensor& sensor) {
  std::vector<Vec3> directions;
  directions.reserve(1 + static_cast<size_t>(sensor.rings) * sensor.azimuths);
  directions.emplace_back(Vec3::UnitX());
  for (int ring = 1; ring <= sensor.rings; ++ring) {
    const double polar = sensor.half_angle_rad * ring / sensor.rings;
    for (int j = 0; j < sensor.azimuths; ++j) {
      const double azimuth = 2.0 * kPi * j / sensor.azimuths;
      // Exact zeros at azimuths 0 and pi keep those rays in the horizontal plane.
      const double vertical = (2 * j == sensor.azimuths || j == 0) ? 0.0 : std::sin(azimuth);
      directions.emplace_back(std::cos(polar), std::sin(polar) * std::cos(azimuth),
                              std::sin(polar) * vertical);
    }
  }
  return directions;
}

namespace {

// Keeps the candidates whose bounding spheres reach into the cone: most of a robot's
// neighbours lie beside or behind a given sensor, and a ray test costs more than this check.
void cull_to_cone(const std::vector<const Body*>& candidates, const Pose& sensor_pose,
                  double half_angle_rad, double max_range_m, std::vector<const Body*>& out) {
  const Vec3 axis = sensor_pose.orientation * Vec3::UnitX();
  out.clear();
  for (const Body* body : candidates) {
    const BoundingSphere sphere = CollisionWorld::bounding_sphere(*body);
    const Vec3 offset = sphere.centre_m - sensor_pose.position_m;
    const double distance = offset.norm();
    if (distance - sphere.radius_m > max_range_m) continue;
    if (distance > sphere.radius_m) {
      const double angle = std::acos(std::clamp(offset.dot(axis) / distance, -1.0, 1.0));
      if (angle > half_angle_rad + std::asin(sphere.radius_m / distance)) continue;
    }
    out.push_back(body);
  }
}

}  // namespace

ConeReading read_cone(const std::vector<const Body*>& candidates, const Pose& sensor_pose,
                      const ConeSensor& sensor, const std::vector<Vec3>& directions) {
  ConeReading best;
  thread_local std::vector<const Body*> in_cone;
  thread_local std::vector<RayTarget> targets;
  cull_to_cone(candidates, sensor_pose, sensor.half_angle_rad, sensor.max_range_m, in_cone);
  targets.clear();
  for (const Body* body : in_cone) {
    const RayTarget target = ray_target(*body, sensor_pose.position_m);
    if (target.min_distance_m <= sensor.max_range_m) targets.push_back(target);
  }
  if (targets.empty()) return best;
  const Eigen::Matrix3d rotation = sensor_pose.orientation.toRotationMatrix();
  for (const Vec3& direction : directions) {
    const double limit = std::min(best.distance_m, sensor.max_range_m);
    const RayHit hit = ray_cast_targets(targets, rotation * direction, limit);
    if (hit.handle < 0 || hit.distance_m >= best.distance_m) continue;
    best.distance_m = hit.distance_m;
    best.handle = hit.handle;
    best.point_m = direction * hit.distance_m;
    best.normal = rotation.transpose() * hit.normal;
  }
  return best;
}

}  // namespace evc
