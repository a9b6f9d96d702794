// The per-image set-up of the ray-cast camera: which objects can appear, and where.
//
// 1. Broadphase: the objects whose Bullet boxes overlap the box around the view pyramid (apex at
//    the camera, base at depth far_m).
// 2. Bounding spheres against the pyramid's six planes drop most of the rest.
// 3. Each survivor's box (a cylinder's or sphere's enclosing box) is projected into the image.
//    Only its part at depths from d / max_ray_length to far_m can be hit, d being the camera's
//    distance to the object, because a hit at depth s on a ray of length L lies s L >= d away,
//    and no pixel keeps a hit beyond far_m. That part is a convex polytope whose vertices are the
//    box corners between those depths and the points where box edges cross either; central
//    projection keeps convexity, so the pixel rectangle around the projected vertices holds
//    every pixel whose ray can meet the object within far_m. (A wall reaching past far_m costs
//    only the pixels of its part within it: before the far cut, a wall across the room had every
//    pixel beyond far_m test it.)
// Every bound is conservative (padded by a pixel or a relative 1e-9): culling only saves work,
// the exact per-pixel intersection decides.
#include "camera_culling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "world/body.hpp"
#include "world/bullet_conversions.hpp"

namespace evc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMarginPx = 1.0;       // added around every pixel rectangle
constexpr double kShrink = 1.0 - 1e-9;  // applied to every lower bound on a depth
constexpr double kGrow = 1.0 + 1e-9;    // and to every upper bound

// The view pyramid in the camera frame: four side planes through the camera, normals pointing
// in, and the base x = far_m.
struct ViewPyramid {
  btVector3 sides[4];
  double far_m;
};

// Image-space extent (slopes u = -y/x, v = -z/x) and nearest depth of a set of camera-frame
// points in front of the camera.
struct Extent {
  double min_depth_m = kInf;
  double min_u = kInf, max_u = -kInf, min_v = kInf, max_v = -kInf;

  void add(const btVector3& p) {
    min_depth_m = std::min(min_depth_m, p.x());
    const double u = -p.y() / p.x(), v = -p.z() / p.x();
    min_u = std::min(min_u, u);
    max_u = std::max(max_u, u);
    min_v = std::min(min_v, v);
    max_v = std::max(max_v, v);
  }
  bool empty() const { return min_depth_m == kInf; }
};

btVector3 enclosing_half_extents(const Primitive& primitive) {
  switch (primitive.kind) {
    case Primitive::Kind::kBox:
      return primitive.half_extents;
    case Primitive::Kind::kCylinder:
      return btVector3(primitive.radius_m, primitive.radius_m, primitive.half_height_m);
    case Primitive::Kind::kSphere:
      break;
  }
  return btVector3(primitive.radius_m, primitive.radius_m, primitive.radius_m);
}

// Distance from a point (object frame) to the primitive: 0 on its surface and inside.
double distance_to_primitive(const Primitive& primitive, const btVector3& point) {
  switch (primitive.kind) {
    case Primitive::Kind::kBox: {
      btVector3 outside;
      for (int axis = 0; axis < 3; ++axis) {
        outside[axis] = std::max(std::abs(point[axis]) - primitive.half_extents[axis], 0.0);
      }
      return outside.length();
    }
    case Primitive::Kind::kCylinder: {
      const double radial = std::max(
          std::sqrt(point.x() * point.x() + point.y() * point.y()) - primitive.radius_m, 0.0);
      const double axial = std::max(std::abs(point.z()) - primitive.half_height_m, 0.0);
      return std::sqrt(radial * radial + axial * axial);
    }
    case Primitive::Kind::kSphere:
      break;
  }
  return std::max(point.length() - primitive.radius_m, 0.0);
}

bool strictly_inside(const Primitive& primitive, const btVector3& point) {
  switch (primitive.kind) {
    case Primitive::Kind::kBox:
      return std::abs(point.x()) < primitive.half_extents.x() &&
             std::abs(point.y()) < primitive.half_extents.y() &&
             std::abs(point.z()) < primitive.half_extents.z();
    case Primitive::Kind::kCylinder:
      return point.x() * point.x() + point.y() * point.y() <
                 primitive.radius_m * primitive.radius_m &&
             std::abs(point.z()) < primitive.half_height_m;
    case Primitive::Kind::kSphere:
      break;
  }
  return point.length2() < primitive.radius_m * primitive.radius_m;
}

// Extent of the part of a box (camera-frame corners, corner k has bit i set for +half_i) at
// depths in [min_depth_m, max_depth_m], 0 < min_depth_m < max_depth_m. Its vertices are the
// corners in that slab and the points where box edges cross either of its planes.
Extent slab_extent(const btVector3 (&corners)[8], double min_depth_m, double max_depth_m) {
  Extent extent;
  for (int k = 0; k < 8; ++k) {
    const double x = corners[k].x();
    if (x >= min_depth_m && x <= max_depth_m) extent.add(corners[k]);
    for (int bit = 1; bit < 8; bit <<= 1) {
      if ((k & bit) != 0) continue;
      const btVector3& a = corners[k];
      const btVector3& b = corners[k | bit];
      for (const double plane : {min_depth_m, max_depth_m}) {
        if ((a.x() < plane) == (b.x() < plane)) continue;
        btVector3 crossing = a.lerp(b, (plane - a.x()) / (b.x() - a.x()));
        crossing.setX(plane);  // on the plane by construction; keeps x > 0 despite rounding
        extent.add(crossing);
      }
    }
  }
  return extent;
}

// First pixel index whose slope reaches @p slope, and one past the last below @p slope, padded.
int first_pixel(double slope, double focal_px, int count) {
  const double pixel = std::floor(slope * focal_px + 0.5 * count - 0.5 - kMarginPx);
  return static_cast<int>(std::clamp(pixel, 0.0, static_cast<double>(count)));
}
int end_pixel(double slope, double focal_px, int count) {
  const double pixel = std::ceil(slope * focal_px + 0.5 * count - 0.5 + kMarginPx) + 1.0;
  return static_cast<int>(std::clamp(pixel, 0.0, static_cast<double>(count)));
}

ViewPyramid view_pyramid(const CameraRays& rays, const CameraSpec& spec) {
  const double pad = kMarginPx / rays.focal_px;
  const double u_lo = rays.col_slope.front() - pad, u_hi = rays.col_slope.back() + pad;
  const double v_lo = rays.row_slope.front() - pad, v_hi = rays.row_slope.back() + pad;
  // Inside: u_lo <= -y/x <= u_hi and v_lo <= -z/x <= v_hi, multiplied out by x > 0.
  return ViewPyramid{{btVector3(-u_lo, -1, 0).normalized(), btVector3(u_hi, 1, 0).normalized(),
                      btVector3(-v_lo, 0, -1).normalized(), btVector3(v_hi, 0, 1).normalized()},
                     spec.far_m};
}

bool sphere_outside(const ViewPyramid& pyramid, const btVector3& centre, double radius_m) {
  if (centre.x() < -radius_m || centre.x() - radius_m > pyramid.far_m) return true;
  for (const btVector3& side : pyramid.sides) {
    if (side.dot(centre) < -radius_m) return true;
  }
  return false;
}

// The world box around the view pyramid, for the broadphase query.
void pyramid_box(const CameraRays& rays, const CameraSpec& spec, Vec3& lo, Vec3& hi) {
  const double pad = kMarginPx / rays.focal_px;
  lo = hi = to_eigen(rays.position_m);
  for (const double u : {rays.col_slope.front() - pad, rays.col_slope.back() + pad}) {
    for (const double v : {rays.row_slope.front() - pad, rays.row_slope.back() + pad}) {
      const Vec3 corner = to_eigen(rays.position_m + rays.rotation * btVector3(1, -u, -v) *
                                                         spec.far_m);
      lo = lo.cwiseMin(corner);
      hi = hi.cwiseMax(corner);
    }
  }
}

// Fills everything but the pixel rectangle and depth bound.
CameraTarget target_frame(const Body& body, const CameraRays& rays) {
  const btTransform& transform = body.object->getWorldTransform();
  CameraTarget target;
  target.primitive = &body.primitive;
  target.handle = body.handle;
  target.rgb = body.rgb;
  target.basis = transform.getBasis();
  target.origin = transform.invXform(rays.position_m);
  const btMatrix3x3 camera_in_object = target.basis.transposeTimes(rays.rotation);
  target.forward = camera_in_object.getColumn(0);
  target.left = camera_in_object.getColumn(1);
  target.up = camera_in_object.getColumn(2);
  return target;
}

// Sets the pixel rectangle and depth bound; false when no pixel ray can meet the object.
bool bound_in_image(const Body& body, const CameraRays& rays, const CameraSpec& spec,
                    CameraTarget& target) {
  const double distance_m = distance_to_primitive(body.primitive, target.origin);
  const double min_depth_m = distance_m / rays.max_ray_length * kShrink;
  if (!(min_depth_m > 0.0)) {  // the camera touches the object: any pixel may see it, at 0 m
    target.camera = strictly_inside(body.primitive, target.origin)
                        ? CameraTarget::Camera::kInside
                        : CameraTarget::Camera::kOnSurface;
    target.row_end = spec.height;
    target.col_end = spec.width;
    return true;
  }
  const btVector3 half = enclosing_half_extents(body.primitive);
  // Box corners in the camera frame: the object's axes there are the rows of camera_in_object.
  const btVector3 centre = (body.object->getWorldTransform().getOrigin() - rays.position_m) *
                           rays.rotation;
  const btVector3 axes[3] = {btVector3(target.forward[0], target.left[0], target.up[0]) * half[0],
                             btVector3(target.forward[1], target.left[1], target.up[1]) * half[1],
                             btVector3(target.forward[2], target.left[2], target.up[2]) * half[2]};
  btVector3 corners[8];
  for (int k = 0; k < 8; ++k) {
    corners[k] = centre;
    for (int axis = 0; axis < 3; ++axis) {
      corners[k] += ((k >> axis) & 1) ? axes[axis] : -axes[axis];
    }
  }
  // No pixel takes a hit beyond far_m: the part beyond it cannot be seen.
  if (min_depth_m > spec.far_m) return false;
  const Extent extent = slab_extent(corners, min_depth_m, spec.far_m * kGrow);
  if (extent.empty()) return false;
  target.min_depth_m = extent.min_depth_m * kShrink;
  target.col_begin = first_pixel(extent.min_u, rays.focal_px, spec.width);
  target.col_end = end_pixel(extent.max_u, rays.focal_px, spec.width);
  target.row_begin = first_pixel(extent.min_v, rays.focal_px, spec.height);
  target.row_end = end_pixel(extent.max_v, rays.focal_px, spec.height);
  return target.col_begin < target.col_end && target.row_begin < target.row_end;
}

}  // namespace

CameraRays camera_rays(const Pose& camera_pose, const CameraSpec& spec) {
  CameraRays rays;
  rays.position_m = to_bt(camera_pose.position_m);
  const Quat q = camera_pose.orientation.normalized();
  rays.rotation.setRotation(btQuaternion(q.x(), q.y(), q.z(), q.w()));
  rays.focal_px = 0.5 * spec.height / std::tan(0.5 * spec.vertical_fov_rad);
  rays.col_slope.resize(spec.width);
  rays.row_slope.resize(spec.height);
  for (int col = 0; col < spec.width; ++col) {
    rays.col_slope[col] = (col + 0.5 - 0.5 * spec.width) / rays.focal_px;
  }
  for (int row = 0; row < spec.height; ++row) {
    rays.row_slope[row] = (row + 0.5 - 0.5 * spec.height) / rays.focal_px;
  }
  rays.max_ray_length = std::sqrt(1.0 + rays.col_slope.front() * rays.col_slope.front() +
                                  rays.row_slope.front() * rays.row_slope.front());
  return rays;
}

std::vector<CameraTarget> camera_targets(const CollisionWorld& world, const CameraRays& rays,
                                         const CameraSpec& spec, int ignore_handle, int mask) {
  Vec3 lo, hi;
  pyramid_box(rays, spec, lo, hi);
  std::vector<const Body*> candidates;
  world.overlap_query(lo, hi, mask, ignore_handle, candidates);

  const ViewPyramid pyramid = view_pyramid(rays, spec);
  std::vector<CameraTarget> targets;
  for (const Body* body : candidates) {
    const BoundingSphere sphere = CollisionWorld::bounding_sphere(*body);
    if (sphere_outside(pyramid, (to_bt(sphere.centre_m) - rays.position_m) * rays.rotation,
                       sphere.radius_m)) {
      continue;
    }
    CameraTarget target = target_frame(*body, rays);
    if (bound_in_image(*body, rays, spec, target)) targets.push_back(target);
  }
  std::sort(targets.begin(), targets.end(), [](const CameraTarget& a, const CameraTarget& b) {
    return a.min_depth_m != b.min_depth_m ? a.min_depth_m < b.min_depth_m : a.handle < b.handle;
  });
  return targets;
}

}  // namespace evc
