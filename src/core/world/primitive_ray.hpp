// Internal: exact ray intersection with the primitives a CollisionWorld holds, in the
// primitive's own frame (centred at the origin, cylinder axis = z).
#pragma once

#include <LinearMath/btVector3.h>

namespace evc {

struct Primitive {
  enum class Kind { kBox, kCylinder, kSphere };
  Kind kind = Kind::kBox;
  btVector3 half_extents{0, 0, 0};  // box only
  double radius_m = 0.0;            // cylinder and sphere
  double half_height_m = 0.0;       // cylinder only
};

// Entry distance and outward normal of the ray origin + t * direction (unit), 0 <= t <= t_max.
// A ray starting inside reports t = 0 and normal = -direction: the sensor is buried in the
// object, and the closest possible reading is the honest one.
bool intersect_primitive(const Primitive& primitive, const btVector3& origin,
                         const btVector3& direction, double t_max, double& t, btVector3& normal);

}  // namespace evc
