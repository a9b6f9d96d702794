#include "epuck_vrep_compat/ray_camera.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace evc {
namespace {

// From above and to the side, so walls facing different ways shade differently.
const Vec3 kLightDirection = Vec3(0.4, 0.3, 0.866).normalized();
constexpr double kAmbient = 0.35;
constexpr double kDiffuse = 0.65;

void check_spec(const Pose& pose, const CameraSpec& spec) {
  if (!pose.position_m.allFinite() || !pose.orientation.coeffs().allFinite() ||
      pose.orientation.coeffs().norm() < 1e-9) {
    throw std::invalid_argument("camera position and quaternion must be finite, non-zero");
  }
  if (spec.width < 1 || spec.height < 1) {
    throw std::invalid_argument("width and height must be >= 1");
  }
  if (!(spec.vertical_fov_rad > 0.0 && spec.vertical_fov_rad < 3.14159265358979)) {
    throw std::invalid_argument("vertical_fov_rad must be in (0, pi)");
  }
  if (!(spec.near_m > 0.0 && spec.near_m < spec.far_m && spec.far_m <= kWorldLimit_m)) {
    throw std::invalid_argument("need 0 < near_m < far_m <= 1e6");
  }
}

std::uint8_t to_byte(double channel) {
  return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(channel, 0.0, 1.0)));
}

}  // namespace

CameraImage render(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                   int ignore_handle, int mask) {
  check_spec(camera_pose, spec);
  const Eigen::Matrix3d rotation = camera_pose.orientation.normalized().toRotationMatrix();
  const double focal_px = 0.5 * spec.height / std::tan(0.5 * spec.vertical_fov_rad);
  CameraImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgb.resize(static_cast<size_t>(spec.width) * spec.height * 3);
  image.depth_m.resize(static_cast<size_t>(spec.width) * spec.height);
  for (int row = 0; row < spec.height; ++row) {
    for (int col = 0; col < spec.width; ++col) {
      const Vec3 ray(1.0, -(col + 0.5 - 0.5 * spec.width) / focal_px,
                     -(row + 0.5 - 0.5 * spec.height) / focal_px);
      const double length = ray.norm();  // the axial component of the unit ray is 1 / length
      const RayHit hit = world.ray_cast(camera_pose.position_m, rotation * (ray / length),
                                        spec.far_m * length, ignore_handle, mask);
      Vec3 colour = world.background();
      double depth = spec.far_m;
      if (hit.handle >= 0) {
        colour = hit.rgb * (kAmbient + kDiffuse * std::abs(hit.normal.dot(kLightDirection)));
        depth = std::clamp(hit.distance_m / length, spec.near_m, spec.far_m);
      }
      const size_t pixel = static_cast<size_t>(row) * spec.width + col;
      for (int c = 0; c < 3; ++c) image.rgb[3 * pixel + c] = to_byte(colour[c]);
      image.depth_m[pixel] = static_cast<float>(depth);
    }
  }
  return image;
}

}  // namespace evc
