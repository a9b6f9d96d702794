// The ray-cast camera: camera_culling finds the few objects that can appear and the pixel
// rectangle of each; they are drawn nearest first into a depth buffer, each pixel of a rectangle
// intersecting its exact ray with the object unless a nearer hit already covers the pixel.
//
// The hit tests are primitive_ray's closed forms, specialised for a camera outside the object:
// only the faces (box), cap and side (cylinder) the camera can see are tested, the entry point
// is checked against the other slabs instead of clipping a whole interval, and |n · L|, not the
// normal, is what is kept. A camera on an object's surface uses primitive_ray itself.
#include "epuck_vrep_compat/render/ray_camera.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <thread>

#include "camera_culling.hpp"
#include "world/bullet_conversions.hpp"

namespace evc {
namespace {

// From above and to the side, so walls facing different ways shade differently.
const Vec3 kLightDirection = Vec3(0.4, 0.3, 0.866).normalized();
constexpr double kAmbient = 0.35;
constexpr double kDiffuse = 0.65;
constexpr std::size_t kKeptPixels = 1 << 20;  // a larger image's scratch is freed after it
// A batch takes another thread only for this many images each: starting one costs about as
// much as rendering a small image.
constexpr std::size_t kImagesPerThread = 4;

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
  const double x = 255.0 * std::min(std::max(channel, 0.0), 1.0);
  return static_cast<std::uint8_t>(static_cast<int>(x + 0.5) * (x >= 0.5));
}

// Every hit test below: true for a hit at depth <= limit_m along the pixel ray
// origin + depth * ray (object frame), with the hit's |n · L| in cosine.

// A face that the camera sees: the plane x_axis = side * half_axis with the camera beyond it.
// A ray from outside a convex object crosses at most one such face, and then enters through it.
// Crossing tests are multiplied out by the ray's component along the axis, so only a hit
// costs a division.
struct VisibleFace {
  int axis, u, v;       // the face's normal axis and the two axes spanning it
  double side;          // +1 for the face at +half, -1 for -half
  double offset_m;      // face plane minus camera, along the axis (sign -side)
  double half_u_m, half_v_m;
  double cosine;        // |n · L|

  // True when the ray crosses the face; then depth = offset_m / ray[axis].
  bool crossed(const btVector3& origin, const btVector3& ray) const {
    const double speed = -side * ray[axis];  // towards the plane; depth = -side offset / speed
    if (speed <= 0.0) return false;
    // |origin_j + depth ray_j| <= half_j, times speed.
    const double reach = -side * offset_m;   // depth times speed, > 0
    return std::abs(speed * origin[u] + reach * ray[u]) <= speed * half_u_m &&
           std::abs(speed * origin[v] + reach * ray[v]) <= speed * half_v_m;
  }
};

VisibleFace visible_face(int axis, double side, double half_m, const btVector3& half,
                         const btVector3& origin, const btVector3& light) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return VisibleFace{axis,    u,       v,       side, side * half_m - origin[axis],
                     half[u], half[v], std::abs(light[axis])};
}

class BoxHit {
 public:
  BoxHit(const CameraTarget& target, const btVector3& light) : origin_(target.origin) {
    const btVector3& half = target.primitive->half_extents;
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(origin_[axis]) <= half[axis]) continue;
      const double side = origin_[axis] > 0.0 ? 1.0 : -1.0;
      faces_[count_++] = visible_face(axis, side, half[axis], half, origin_, light);
    }
  }

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    for (int f = 0; f < count_; ++f) {
      const VisibleFace& face = faces_[f];
      if (!face.crossed(origin_, ray)) continue;
      depth_m = face.offset_m / ray[face.axis];
      cosine = face.cosine;
      return depth_m <= limit_m;
    }
    return false;
  }

 private:
  btVector3 origin_;
  VisibleFace faces_[3];
  int count_ = 0;
};

// A cylinder seen from outside: enters through the cap facing the camera, if the camera sees
// one and the ray crosses it, or else through the round side at the near root of
// |origin_xy + t ray_xy|^2 = r^2 (solved as primitive_ray does), if that point is between the caps.
class CylinderHit {
 public:
  CylinderHit(const CameraTarget& target, const btVector3& light)
      : origin_(target.origin), radius_m_(target.primitive->radius_m),
        half_height_m_(target.primitive->half_height_m), light_over_radius_(light / radius_m_),
        cap_cosine_(std::abs(light.z())) {
    side_c_ = origin_.x() * origin_.x() + origin_.y() * origin_.y() - radius_m_ * radius_m_;
    if (std::abs(origin_.z()) > half_height_m_) {
      const double side = origin_.z() > 0.0 ? 1.0 : -1.0;
      cap_offset_m_ = side * half_height_m_ - origin_.z();
      cap_side_ = side;
    }
  }

  bool operator()(const btVector3& ray, double limit_m, double& depth_m, double& cosine) const {
    if (cap_side_ * ray.z() < 0.0) {  // |origin_xy + t ray_xy| <= r at t = offset / ray_z
      const double x = origin_.x() * ray.z() + cap_offset_m_ * ray.x();
      const double y = origin_.y() * ray.z() + cap_offset_m_ * ray.y();
      if (x * x + y * y <= radius_m_ * radius_m_ * ray.z() * ray.z()) {
        depth_m = cap_offset_m_ / ray.z();
        cosine = cap_cosine_;
        return depth_m <= limit_m;
      }
    }
    if (side_c_ <= 0.0) return false;  // inside the round side's extension: the cap or nothing
    const double b = origin_.x() * ray.x() + origin_.y() * ray.y();
    if (b >= 0.0) return false;
    const double a = ray.x() * ray.x() + ray.y() * ray.y();
    const double discriminant = b * b - a * side_c_;
    if (discriminant < 0.0) return false;
    const double t = side_c_ / (std::sqrt(discriminant) - b);
    if (t > limit_m || std::abs(origin_.z() + t * ray.z()) > half_height_m_) return false;
    const double x = origin_.x() + t * ray.x(), y = origin_.y() + t * ray.y();
    depth_m = t;
    cosine = std::abs(x * light_over_radius_.x() + y * light_over_radius_.y());  // n = (x, y)/r
    return true;
  }

 private:
  btVector3 origin_;
  double radius_m_, half_height_m_;
  btVector3 light_over_radius_;
  double cap_cosine_;
  double side_c_;              // |origin_xy|^2 - r^2, > 0 outside the round side
  double cap_side_ = 0.0;      // +1 / -1: the camera sees the top / bottom cap, 0: neither
  double cap_offset_m_ = 0.0;  // that cap's plane minus camera, along z
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

// Per pixel, the nearest hit so far: its depth (far_m until something is hit), its colour (index
// into a table: 0 is the background, k + 1 target k) and shade (ambient + diffuse |n · L|; 1 for
// the background, whose colour is not shaded). Kept per thread between images: allocating it
// afresh (page faults on some 400 kB) cost about half as much as rendering 160 x 120.
// The shade is kept only when the colour image is asked for (kShade).
struct DepthBuffer {
  std::vector<double> depth_m;
  std::vector<int> colour;
  std::vector<double> shade;

  void reset(std::size_t pixels, double far_m, bool shaded) {
    depth_m.assign(pixels, far_m);
    colour.assign(pixels, 0);
    if (shaded) shade.assign(pixels, 1.0);
  }
};

// Tests a target's pixel rectangle. As in CollisionWorld::ray_cast, a hit replaces a strictly
// farther one only, so exact ties go to the target drawn first. Without kShade, the hit's
// |n · L| is not stored (and, the hit test inlined, not computed): depth and colour index are
// those of the shaded drawing.
template <bool kShade, class Hit>
void draw(const CameraTarget& target, int colour, const Hit& hit, const CameraRays& rays,
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
      if (depth_m >= nearest_m && buffer.colour[pixel] != 0) continue;
      buffer.depth_m[pixel] = depth_m;
      buffer.colour[pixel] = colour;
      if (kShade) buffer.shade[pixel] = kAmbient + kDiffuse * cosine;
    }
  }
}

template <bool kShade>
void draw(const CameraTarget& target, int colour, const CameraRays& rays, int width,
          DepthBuffer& buffer) {
  const btVector3 light = to_bt(kLightDirection) * target.basis;  // in the object's frame
  if (target.camera == CameraTarget::Camera::kInside) {
    draw<kShade>(target, colour, InsideHit(light), rays, width, buffer);
    return;
  }
  if (target.camera == CameraTarget::Camera::kOnSurface) {
    draw<kShade>(target, colour, AnyHit(target, light), rays, width, buffer);
    return;
  }
  switch (target.primitive->kind) {
    case Primitive::Kind::kBox:
      draw<kShade>(target, colour, BoxHit(target, light), rays, width, buffer);
      break;
    case Primitive::Kind::kCylinder:
      draw<kShade>(target, colour, CylinderHit(target, light), rays, width, buffer);
      break;
    case Primitive::Kind::kSphere:
      draw<kShade>(target, colour, SphereHit(target, light), rays, width, buffer);
      break;
  }
}

}  // namespace

void render_into(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                 int ignore_handle, int mask, std::uint8_t* rgb, float* depth_out) {
  check_spec(camera_pose, spec);
  if (rgb == nullptr && depth_out == nullptr) return;
  const CameraRays rays = camera_rays(camera_pose, spec);
  const std::vector<CameraTarget> targets =
      camera_targets(world, rays, spec, ignore_handle, mask);
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  const bool shaded = rgb != nullptr;
  thread_local DepthBuffer buffer;
  buffer.reset(pixels, spec.far_m, shaded);
  std::vector<double> colours(world.background().data(), world.background().data() + 3);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    if (shaded) {
      draw<true>(targets[k], static_cast<int>(k + 1), rays, spec.width, buffer);
    } else {
      draw<false>(targets[k], static_cast<int>(k + 1), rays, spec.width, buffer);
    }
    colours.insert(colours.end(), targets[k].rgb.data(), targets[k].rgb.data() + 3);
  }
  // Plain pointers: byte stores through the vector would make the compiler reload everything.
  const double* shade = buffer.shade.data();
  const int* colour = buffer.colour.data();
  const double* depth_m = buffer.depth_m.data();
  if (shaded) {
    for (std::size_t pixel = 0; pixel < pixels; ++pixel) {
      const double* base = &colours[3 * colour[pixel]];
      rgb[3 * pixel] = to_byte(base[0] * shade[pixel]);
      rgb[3 * pixel + 1] = to_byte(base[1] * shade[pixel]);
      rgb[3 * pixel + 2] = to_byte(base[2] * shade[pixel]);
    }
  }
  if (depth_out != nullptr) {
    for (std::size_t pixel = 0; pixel < pixels; ++pixel) {
      depth_out[pixel] = static_cast<float>(std::clamp(depth_m[pixel], spec.near_m, spec.far_m));
    }
  }
  if (pixels > kKeptPixels) buffer = DepthBuffer();  // do not hold on to a huge image's memory
}

CameraImage render(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                   int ignore_handle, int mask) {
  check_spec(camera_pose, spec);
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  CameraImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgb.resize(3 * pixels);
  image.depth_m.resize(pixels);
  render_into(world, camera_pose, spec, ignore_handle, mask, image.rgb.data(),
              image.depth_m.data());
  return image;
}

void render_rgb_batch(const CollisionWorld& world, const std::vector<Pose>& camera_poses,
                      const std::vector<int>& ignore_handles, const CameraSpec& spec, int mask,
                      int threads, std::uint8_t* rgb_out) {
  if (ignore_handles.size() != camera_poses.size()) {
    throw std::invalid_argument("one ignore handle per camera pose expected");
  }
  if (threads < 1) throw std::invalid_argument("threads must be >= 1");
  for (const Pose& pose : camera_poses) check_spec(pose, spec);
  const std::size_t count = camera_poses.size();
  const std::size_t image_bytes = 3 * static_cast<std::size_t>(spec.width) * spec.height;
  auto render_range = [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      render_into(world, camera_poses[k], spec, ignore_handles[k], mask,
                  rgb_out + k * image_bytes, nullptr);
    }
  };
  // Images are dealt out in contiguous runs; the calling thread renders the first run.
  const std::size_t workers =
      std::min<std::size_t>(static_cast<std::size_t>(threads), count / kImagesPerThread);
  if (workers <= 1) {
    render_range(0, count);
    return;
  }
  std::vector<std::thread> helpers;
  helpers.reserve(workers - 1);
  std::vector<std::exception_ptr> errors(workers);
  for (std::size_t w = 1; w < workers; ++w) {
    helpers.emplace_back([&, w] {
      try {
        render_range(w * count / workers, (w + 1) * count / workers);
      } catch (...) {
        errors[w] = std::current_exception();
      }
    });
  }
  try {
    render_range(0, count / workers);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (std::thread& helper : helpers) helper.join();
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace evc
