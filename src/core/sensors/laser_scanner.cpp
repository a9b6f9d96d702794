#include "epuck_vrep_compat/sensors/laser_scanner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "world/body.hpp"
#include "world/pose_checks.hpp"

namespace evc {
namespace {

bool finite_non_negative(double value) { return std::isfinite(value) && value >= 0.0; }

void validate(const LaserSpec& spec) {
  if (!std::isfinite(spec.angle_min_rad) || !std::isfinite(spec.angle_increment_rad)) {
    throw std::invalid_argument("angle_min_rad and angle_increment_rad must be finite");
  }
  if (spec.count < 1) throw std::invalid_argument("count must be >= 1");
  if (!(spec.range_min_m >= 0.0 && spec.range_min_m < spec.range_max_m &&
        spec.range_max_m <= kWorldLimit_m)) {
    throw std::invalid_argument("need 0 <= range_min_m < range_max_m <= 1e6");
  }
  if (!finite_non_negative(spec.sigma_min_m)) {
    throw std::invalid_argument("sigma_min_m must be finite and >= 0");
  }
  if (!finite_non_negative(spec.sigma_rel)) {
    throw std::invalid_argument("sigma_rel must be finite and >= 0");
  }
}

// The objects a beam can hit, each made ready for rays from the scanner's origin: those in
// range whose bounding spheres cross the scan plane (with a little slack, so that rounding
// keeps a body rather than drops it).
void scan_targets(const CollisionWorld& world, const Pose& pose, const LaserSpec& spec,
                  int ignore_handle, int mask, std::vector<RayTarget>& targets) {
  thread_local std::vector<const Body*> candidates;
  candidates.clear();
  const Vec3 reach = Vec3::Constant(spec.range_max_m);
  world.overlap_query(pose.position_m - reach, pose.position_m + reach, mask, ignore_handle,
                      candidates);
  const Vec3 plane_normal = pose.orientation * Vec3::UnitZ();
  targets.clear();
  for (const Body* body : candidates) {
    const BoundingSphere sphere = CollisionWorld::bounding_sphere(*body);
    const Vec3 offset = sphere.centre_m - pose.position_m;
    const double slack = 1e-9 * (1.0 + offset.norm() + sphere.radius_m);
    if (std::abs(offset.dot(plane_normal)) > sphere.radius_m + slack) continue;
    const RayTarget target = ray_target(*body, pose.position_m);
    if (target.min_distance_m <= spec.range_max_m) targets.push_back(target);
  }
}

}  // namespace

LaserScanner::LaserScanner(const LaserSpec& spec, std::uint64_t seed) : spec_(spec), rng_(seed) {
  validate(spec);
  beams_.reserve(static_cast<std::size_t>(spec.count));
  for (int k = 0; k < spec.count; ++k) {
    const double angle = spec.angle_min_rad + k * spec.angle_increment_rad;
    beams_.emplace_back(std::cos(angle), std::sin(angle), 0.0);
  }
}

std::vector<float> LaserScanner::scan(const CollisionWorld& world, const Pose& pose,
                                      int ignore_handle, int mask) {
  const Pose scanner = checked_pose(pose);
  thread_local std::vector<RayTarget> targets;
  scan_targets(world, scanner, spec_, ignore_handle, mask, targets);
  const Eigen::Matrix3d rotation = scanner.orientation.toRotationMatrix();
  const bool noisy = spec_.sigma_min_m > 0.0 || spec_.sigma_rel > 0.0;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> ranges(beams_.size(), kInf);
  for (std::size_t k = 0; k < beams_.size(); ++k) {
    const double unit_noise = noisy ? rng_.normal() : 0.0;
    if (targets.empty()) continue;
    const RayHit hit = ray_cast_targets(targets, rotation * beams_[k], spec_.range_max_m);
    if (hit.handle < 0) continue;
    if (hit.distance_m < spec_.range_min_m) {
      ranges[k] = -kInf;
      continue;
    }
    const double sigma_m = std::max(spec_.sigma_min_m, spec_.sigma_rel * hit.distance_m);
    ranges[k] = static_cast<float>(std::clamp(hit.distance_m + sigma_m * unit_noise,
                                              spec_.range_min_m, spec_.range_max_m));
  }
  return ranges;
}

}  // namespace evc
