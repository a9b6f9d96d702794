#include "primitive_ray.hpp"

#include <cmath>
#include <limits>

namespace evc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The parameter interval where a ray is inside a convex primitive, and the outward normal of
// the surface it enters through.
struct Interval {
  double enter = -kInf;
  double exit = kInf;
  btVector3 normal{0, 0, 0};
  bool unit = true;  // the normal is a unit axis already (a slab's), which normalising keeps
};

// Clips the interval by the slab |x_axis| <= half; false when the ray misses the slab.
bool clip_slab(double origin, double direction, double half, int axis, Interval& in) {
  if (direction == 0.0) return std::abs(origin) <= half;
  const double inverse = 1.0 / direction;
  double near = (-half - origin) * inverse;
  double far = (half - origin) * inverse;
  if (near > far) std::swap(near, far);
  if (near > in.enter) {
    in.enter = near;
    in.normal.setZero();
    in.normal[axis] = direction > 0.0 ? -1.0 : 1.0;
    in.unit = true;
  }
  if (far < in.exit) in.exit = far;
  return in.enter <= in.exit;
}

// Roots of a t^2 + 2 b t + c = 0 (a > 0) in the numerically stable form; false if none.
bool solve_quadratic(double a, double b, double c, double& t0, double& t1) {
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return false;
  const double q = -(b + std::copysign(std::sqrt(discriminant), b));
  if (q == 0.0) {  // b == 0 and a tangent ray through the centre line: c == 0
    t0 = t1 = 0.0;
    return true;
  }
  t0 = q / a;
  t1 = c / q;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

// Clips the interval by the infinite circular cylinder x^2 + y^2 <= r^2 (axis z).
bool clip_round_side(const btVector3& o, const btVector3& d, double radius, Interval& in) {
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = o.x() * d.x() + o.y() * d.y();
  const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
  if (a == 0.0) return c <= 0.0;  // parallel to the axis: inside for all t, or never
  double near = 0.0, far = 0.0;
  if (!solve_quadratic(a, b, c, near, far)) return false;
  if (near > in.enter) {
    in.enter = near;
    const btVector3 p = o + d * near;
    in.normal = btVector3(p.x(), p.y(), 0.0) / radius;
    in.unit = false;
  }
  if (far < in.exit) in.exit = far;
  return in.enter <= in.exit;
}

bool clip_sphere(const btVector3& o, const btVector3& d, double radius, Interval& in) {
  double near = 0.0, far = 0.0;
  if (!solve_quadratic(d.length2(), o.dot(d), o.length2() - radius * radius, near, far)) {
    return false;
  }
  in.enter = near;
  in.exit = far;
  in.normal = (o + d * near) / radius;
  in.unit = false;
  return true;
}

bool inside_interval(const Primitive& p, const btVector3& o, const btVector3& d, Interval& in) {
  switch (p.kind) {
    case Primitive::Kind::kBox:
      return clip_slab(o.x(), d.x(), p.half_extents.x(), 0, in) &&
             clip_slab(o.y(), d.y(), p.half_extents.y(), 1, in) &&
             clip_slab(o.z(), d.z(), p.half_extents.z(), 2, in);
    case Primitive::Kind::kCylinder:
      return clip_slab(o.z(), d.z(), p.half_height_m, 2, in) &&
             clip_round_side(o, d, p.radius_m, in);
    case Primitive::Kind::kSphere:
      return clip_sphere(o, d, p.radius_m, in);
  }
  return false;
}

}  // namespace

bool intersect_primitive(const Primitive& primitive, const btVector3& origin,
                         const btVector3& direction, double t_max, double& t, btVector3& normal) {
  Interval in;
  if (!inside_interval(primitive, origin, direction, in)) return false;
  if (in.exit < 0.0 || in.enter > t_max) return false;
  if (in.enter < 0.0) {
    t = 0.0;
    normal = -direction;
  } else {
    t = in.enter;
    // A unit axis normalises to itself, bit for bit: only a curved surface's normal needs it.
    normal = in.unit ? in.normal : in.normal.normalized();
  }
  return true;
}

}  // namespace evc
