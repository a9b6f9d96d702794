// Internal: one object of a CollisionWorld, shared by the world's sources only.
#pragma once

#include <memory>
#include <vector>

#include <btBulletCollisionCommon.h>

#include "epuck_vrep_compat/collision_world.hpp"
#include "epuck_vrep_compat/types.hpp"
#include "primitive_ray.hpp"

namespace evc {

struct Body {
  int handle = -1;
  int group = 0;
  Primitive primitive;
  Vec3 rgb = Vec3::Zero();
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btCollisionObject> object;  // user pointer -> this Body
};

// A body made ready for many rays from one origin (a sensor's): the origin in the body's frame,
// computed once, and a lower bound on the distance of any hit, so that a ray whose reach is
// already shorter skips the body without changing what it reports.
struct RayTarget {
  const Body* body = nullptr;
  btVector3 local_origin;
  double min_distance_m = 0.0;
};

RayTarget ray_target(const Body& body, const Vec3& origin);

// CollisionWorld::ray_cast_bodies for rays from the targets' origin: the same hits, bit for bit.
RayHit ray_cast_targets(const std::vector<RayTarget>& targets, const Vec3& direction_unit,
                        double max_distance_m);

}  // namespace evc
