// The ray-cast camera: camera_culling finds the few objects that can appear and the pixel
// rectangle of each; they are drawn nearest first into a depth buffer, each pixel of a rectangle
// intersecting its exact ray with the object unless a nearer hit already covers the pixel.
//
// The hit tests are primitive_ray's closed forms, specialised for a camera outside the object:
// only the faces (box), cap and side (cylinder) the camera can see are tested, the entry point
// is checked against the other slabs instead of clipping a whole interval, and |n · L|, not the
// normal, is what is kept. A camera on an object's surface uses primitive_ray itself.
#include "epuck_vrep_compat/ray_camera.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bullet_conversions.hpp"
#include "camera_culling.hpp"

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

// std::lround(255 clamp(channel, 0, 1)) without the libm call: for 0.5 <= x <= 255, x + 0.5 is
// rounded to an integer only when it already is one, so truncation rounds half away from zero.
std::uint8_t to_byte(double channel) {
  const double x = 255.0 * std::clamp(channel, 0.0, 1.0);
  return x < 0.5 ? 0 : static_cast<std::uint8_t>(x + 0.5);
}

// Every hit test below: true for a hit at depth <= limit_m along the pixel ray
// origin + depth * ray (object frame), with the hit's |n · L| in cosine.

// A box seen from outside: the entry face is the visible face whose plane the ray reaches last.
class BoxHit {
 public:
  BoxHit(const CameraTarget& target, const btVector3& light)
      : origin_(target.origin), half_(target.primitive->half_extents) {
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(origin_[axis]) <= half_[axis]) continue;
      const double side = origin_[axis] > 0.0 ? 1.0 : -1.0;
      faces_[count_++] = Face{axis, side, side * half_[axis] - origin_[axis], std::abs(light[axis])};
    }
  }

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    double enter = -1.0;
    const Face* entry = nullptr;
    for (int f = 0; f < count_; ++f) {
      const Face& face = faces_[f];
      const double along = ray[face.axis];
      if (along * face.side >= 0.0) return false;  // never reaches this face's plane
      const double t = face.offset_m / along;
      if (t > enter) {
        enter = t;
        entry = &face;
      }
    }
    if (entry == nullptr || enter > limit_m) return false;
    for (int axis = 0; axis < 3; ++axis) {
      if (axis != entry->axis && std::abs(origin_[axis] + enter * ray[axis]) > half_[axis]) {
        return false;
      }
    }
    depth_m = enter;
    cosine = entry->cosine;
    return true;
  }

 private:
  struct Face {
    int axis;
    double side;      // +1 for the face at +half, -1 for -half
    double offset_m;  // face plane minus camera, along the axis
    double cosine;
  };
  btVector3 origin_, half_;
  Face faces_[3];
  int count_ = 0;
};

// A cylinder seen from outside: enters through the cap facing the camera or the round side,
// whichever it reaches last, if that point lies within the other.
class CylinderHit {
 public:
  CylinderHit(const CameraTarget& target, const btVector3& light)
      : origin_(target.origin), radius_m_(target.primitive->radius_m),
        half_height_m_(target.primitive->half_height_m), light_(light) {
    side_c_ = origin_.x() * origin_.x() + origin_.y() * origin_.y() - radius_m_ * radius_m_;
    if (std::abs(origin_.z()) > half_height_m_) cap_side_ = origin_.z() > 0.0 ? 1.0 : -1.0;
    cap_offset_m_ = cap_side_ * half_height_m_ - origin_.z();
  }

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    double enter = -1.0;
    bool through_cap = false;
    if (cap_side_ != 0.0) {
      if (ray.z() * cap_side_ >= 0.0) return false;
      enter = cap_offset_m_ / ray.z();
      through_cap = true;
    }
    if (side_c_ > 0.0) {  // outside the round side: its near root, as primitive_ray solves it
      const double b = origin_.x() * ray.x() + origin_.y() * ray.y();
      if (b >= 0.0) return false;
      const double a = ray.x() * ray.x() + ray.y() * ray.y();
      const double discriminant = b * b - a * side_c_;
      if (discriminant < 0.0) return false;
      const double t = side_c_ / (std::sqrt(discriminant) - b);
      if (t > enter) {
        enter = t;
        through_cap = false;
      }
    }
    if (enter > limit_m) return false;
    const double x = origin_.x() + enter * ray.x(), y = origin_.y() + enter * ray.y();
    if (through_cap) {
      if (x * x + y * y > radius_m_ * radius_m_) return false;
      cosine = std::abs(light_.z());
    } else {
      if (std::abs(origin_.z() + enter * ray.z()) > half_height_m_) return false;
      cosine = std::abs(x * light_.x() + y * light_.y()) / radius_m_;
    }
    depth_m = enter;
    return true;
  }

 private:
  btVector3 origin_;
  double radius_m_, half_height_m_;
  btVector3 light_;
  double side_c_;            // |origin_xy|^2 - r^2, > 0 outside the round side
  double cap_side_ = 0.0;    // +1 / -1: the camera sees the top / bottom cap, 0: neither
  double cap_offset_m_;
};

class SphereHit {
 public:
  SphereHit(const CameraTarget& target, const btVector3& light)
      : origin_(target.origin), radius_m_(target.primitive->radius_m), light_(light),
        c_(origin_.length2() - radius_m_ * radius_m_) {}

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    const double b = origin_.dot(ray);
    if (b >= 0.0) return false;
    const double discriminant = b * b - ray.length2() * c_;
    if (discriminant < 0.0) return false;
    const double t = c_ / (std::sqrt(discriminant) - b);
    if (t > limit_m) return false;
    depth_m = t;
    cosine = std::abs((origin_ + ray * t).dot(light_)) / radius_m_;
    return true;
  }

 private:
  btVector3 origin_;
  double radius_m_;
  btVector3 light_;
  double c_;
};

// The camera strictly inside the object: every ray starts inside, hits at 0 m with n = -ray.
class InsideHit {
 public:
  explicit InsideHit(const btVector3& light) : light_(light) {}

  bool operator()(const btVector3& ray, double, double& depth_m, double& cosine) const {
    depth_m = 0.0;
    cosine = std::abs(ray.dot(light_)) / ray.length();
    return true;
  }

 private:
  btVector3 light_;
};

// Any primitive, camera anywhere, through primitive_ray.
class AnyHit {
 public:
  AnyHit(const CameraTarget& target, const btVector3& light)
      : primitive_(*target.primitive), origin_(target.origin), light_(light) {}

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    btVector3 normal;
    if (!intersect_primitive(primitive_, origin_, ray, limit_m, depth_m, normal)) return false;
    // A ray starting inside reports the normal -ray, which is not unit here.
    cosine = std::abs(normal.dot(light_)) / normal.length();
    return true;
  }

 private:
  const Primitive& primitive_;
  btVector3 origin_;
  btVector3 light_;
};

// Per pixel, the nearest hit so far: its depth (far_m until something is hit), the index of the
// target hit (-1 for none) and |n · L|, n the surface normal.
struct DepthBuffer {
  std::vector<double> depth_m;
  std::vector<int> target;
  std::vector<double> cosine;

  void reset(std::size_t pixels, double far_m) {
    depth_m.assign(pixels, far_m);
    target.assign(pixels, -1);
    cosine.resize(pixels);
  }
};

// Tests a target's pixel rectangle. As in CollisionWorld::ray_cast, a hit replaces a strictly
// farther one only, so exact ties go to the target drawn first.
template <class Hit>
void draw(const CameraTarget& target, int index, const Hit& hit, const CameraRays& rays,
          int width, DepthBuffer& buffer) {
  for (int row = target.row_begin; row < target.row_end; ++row) {
    const btVector3 row_ray = target.forward - target.up * rays.row_slope[row];
    const std::size_t row_first = static_cast<std::size_t>(row) * width;
    for (int col = target.col_begin; col < target.col_end; ++col) {
      const std::size_t pixel = row_first + col;
      const double nearest_m = buffer.depth_m[pixel];
      if (target.min_depth_m > nearest_m) continue;
      double depth_m = 0.0, cosine = 0.0;
      if (!hit(row_ray - target.left * rays.col_slope[col], nearest_m, depth_m, cosine)) continue;
      if (depth_m >= nearest_m && buffer.target[pixel] >= 0) continue;
      buffer.depth_m[pixel] = depth_m;
      buffer.target[pixel] = index;
      buffer.cosine[pixel] = cosine;
    }
  }
}

void draw(const CameraTarget& target, int index, const CameraRays& rays, int width,
          DepthBuffer& buffer) {
  const btVector3 light = to_bt(kLightDirection) * target.basis;  // in the object's frame
  if (target.camera == CameraTarget::Camera::kInside) {
    draw(target, index, InsideHit(light), rays, width, buffer);
    return;
  }
  if (target.camera == CameraTarget::Camera::kOnSurface) {
    draw(target, index, AnyHit(target, light), rays, width, buffer);
    return;
  }
  switch (target.primitive->kind) {
    case Primitive::Kind::kBox:
      draw(target, index, BoxHit(target, light), rays, width, buffer);
      break;
    case Primitive::Kind::kCylinder:
      draw(target, index, CylinderHit(target, light), rays, width, buffer);
      break;
    case Primitive::Kind::kSphere:
      draw(target, index, SphereHit(target, light), rays, width, buffer);
      break;
  }
}

}  // namespace

CameraImage render(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                   int ignore_handle, int mask) {
  check_spec(camera_pose, spec);
  const CameraRays rays = camera_rays(camera_pose, spec);
  const std::vector<CameraTarget> targets =
      camera_targets(world, rays, spec, ignore_handle, mask);
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  thread_local DepthBuffer buffer;
  buffer.reset(pixels, spec.far_m);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    draw(targets[k], static_cast<int>(k), rays, spec.width, buffer);
  }

  CameraImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgb.resize(3 * pixels);
  image.depth_m.resize(pixels);
  const Vec3& background = world.background();
  const std::uint8_t background_rgb[3] = {to_byte(background[0]), to_byte(background[1]),
                                          to_byte(background[2])};
  for (std::size_t pixel = 0; pixel < pixels; ++pixel) {
    std::uint8_t* rgb = &image.rgb[3 * pixel];
    const int hit = buffer.target[pixel];
    if (hit < 0) {
      std::copy(background_rgb, background_rgb + 3, rgb);
      image.depth_m[pixel] = static_cast<float>(spec.far_m);
      continue;
    }
    const Vec3 colour = targets[hit].rgb * (kAmbient + kDiffuse * buffer.cosine[pixel]);
    for (int c = 0; c < 3; ++c) rgb[c] = to_byte(colour[c]);
    image.depth_m[pixel] =
        static_cast<float>(std::clamp(buffer.depth_m[pixel], spec.near_m, spec.far_m));
  }
  return image;
}

}  // namespace evc
