// Internal: one object of a CollisionWorld, shared by the world's sources only.
#pragma once

#include <memory>

#include <btBulletCollisionCommon.h>

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

}  // namespace evc
