// Internal: one object of a CollisionWorld, and the queries on it that the core's own sources
// share (batched box queries, rays from one origin) but the public API does not offer.
#pragma once

#include <memory>
#include <vector>

#include <btBulletCollisionCommon.h>

#include "epuck_vrep_compat/world/collision_world.hpp"
#include "epuck_vrep_compat/world/types.hpp"
#include "primitive_ray.hpp"

namespace evc {

struct Body {
  int handle = -1;
  int group = 0;
  Primitive primitive;
  Vec3 rgb = Vec3::Zero();
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btCollisionObject> object;  // user pointer -> this Body
  bool stale = false;  // moved since the broadphase last learnt its box (CollisionWorld)
};

// A body made ready for many rays from one origin (a sensor's): the origin in the body's frame,
// computed once, and the plane that separates the origin from the body (through the body's
// closest point, square to `toward`). A ray that cannot cross that plane within its reach
// skips the body; it could not have hit it, so nothing it reports changes.
// (ray_cast_targets: the same hits as CollisionWorld::ray_cast_bodies, bit for bit.)
struct RayTarget {
  const Body* body = nullptr;
  btVector3 local_origin;
  btVector3 toward;             // unit, world frame, origin to closest point; zero if touching
  double min_distance_m = 0.0;  // distance to the closest point less a rounding margin
};

RayTarget ray_target(const Body& body, const Vec3& origin);
RayHit ray_cast_targets(const std::vector<RayTarget>& targets, const Vec3& direction_unit,
                        double max_distance_m);

// One box of a batched overlap query.
struct BoxQuery {
  Vec3 min_m;
  Vec3 max_m;
  int ignore_handle = -1;
};

// CollisionWorld::overlap_query for many boxes, with the same answers: box q's objects are
// out[first[q], first[q + 1]), in handle order. One query over the region the boxes span and a
// grid over it cost less than a tree descent per box when the boxes are many and close
// together (a step's robots).
void overlap_query_batch(const CollisionWorld& world, const std::vector<BoxQuery>& queries,
                         int mask, std::vector<std::size_t>& first,
                         std::vector<const Body*>& out);

}  // namespace evc
