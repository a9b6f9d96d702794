// Ray casts and box queries of a CollisionWorld: Bullet's broadphase tree finds the candidate
// objects, closed-form geometry (primitive_ray) finds the exact hit.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <btBulletCollisionCommon.h>

#include "body.hpp"
#include "bullet_conversions.hpp"
#include "epuck_vrep_compat/collision_world.hpp"

namespace evc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

const Body& body_of(const btBroadphaseProxy* proxy) {
  const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
  return *static_cast<const Body*>(object->getUserPointer());
}

// Tests one body in its own frame (the ray's origin already there) and keeps the hit if it is
// the closest so far.
void test_body(const Body& body, const btVector3& local_origin, const btVector3& direction,
               RayHit& best) {
  const btTransform& transform = body.object->getWorldTransform();
  const btVector3 local_direction = direction * transform.getBasis();  // = R^T d
  double t = 0.0;
  btVector3 normal;
  const double limit = best.distance_m;
  if (!intersect_primitive(body.primitive, local_origin, local_direction, limit, t, normal)) {
    return;
  }
  if (t >= limit && best.handle >= 0) return;
  best.distance_m = t;
  best.handle = body.handle;
  best.normal = to_eigen(transform.getBasis() * normal);
  best.rgb = body.rgb;
}

// Distance from a point to a primitive, both in the primitive's frame; 0 inside.
double distance_to_primitive(const Primitive& primitive, const btVector3& point) {
  switch (primitive.kind) {
    case Primitive::Kind::kBox: {
      btVector3 outside = point.absolute() - primitive.half_extents;
      outside.setMax(btVector3(0, 0, 0));
      return outside.length();
    }
    case Primitive::Kind::kCylinder: {
      // Coordinates are within ±kWorldLimit_m, so the squares cannot overflow.
      const double radial = std::max(
          std::sqrt(point.x() * point.x() + point.y() * point.y()) - primitive.radius_m, 0.0);
      const double axial = std::max(std::abs(point.z()) - primitive.half_height_m, 0.0);
      return std::sqrt(radial * radial + axial * axial);
    }
    case Primitive::Kind::kSphere:
      return std::max(point.length() - primitive.radius_m, 0.0);
  }
  return 0.0;
}

class RayCollector : public btDbvt::ICollide {
 public:
  RayCollector(const btVector3& origin, const btVector3& direction, int ignore_handle, int mask,
               RayHit& best)
      : origin_(origin), direction_(direction), ignore_(ignore_handle), mask_(mask),
        best_(best) {}

  void Process(const btDbvtNode* leaf) override {
    const Body& body = body_of(static_cast<const btBroadphaseProxy*>(leaf->data));
    if (body.handle == ignore_ || (body.group & mask_) == 0) return;
    test_body(body, body.object->getWorldTransform().invXform(origin_), direction_, best_);
  }

 private:
  btVector3 origin_;
  btVector3 direction_;
  int ignore_;
  int mask_;
  RayHit& best_;
};

class BoxCollector : public btBroadphaseAabbCallback {
 public:
  BoxCollector(int mask, int ignore_handle, std::vector<const Body*>& out)
      : mask_(mask), ignore_(ignore_handle), out_(out) {}

  bool process(const btBroadphaseProxy* proxy) override {
    const Body& body = body_of(proxy);
    if (body.handle != ignore_ && (body.group & mask_) != 0) out_.push_back(&body);
    return true;
  }

 private:
  int mask_;
  int ignore_;
  std::vector<const Body*>& out_;
};

RayHit no_hit(double max_distance_m) {
  RayHit hit;
  hit.distance_m = max_distance_m;
  return hit;
}

// Turns "closest so far within max" into the public convention: +inf for no hit.
RayHit finished(RayHit hit) {
  if (hit.handle < 0) hit.distance_m = kInf;
  return hit;
}

void check_rays(const Eigen::Ref<const RowMatrixXd>& origins,
                const Eigen::Ref<const RowMatrixXd>& directions, double max_distance_m) {
  if (origins.cols() != 3) throw std::invalid_argument("origins must have shape (M, 3)");
  if (directions.cols() != 3 || directions.rows() != origins.rows()) {
    throw std::invalid_argument("directions must have shape (M, 3), M = len(origins)");
  }
  if (!origins.allFinite()) throw std::invalid_argument("origins must be finite");
  if (!directions.allFinite()) throw std::invalid_argument("directions must be finite");
  if ((directions.rowwise().norm().array() <= 0.0).any()) {
    throw std::invalid_argument("directions must be non-zero");
  }
  if (!(max_distance_m >= 0.0)) throw std::invalid_argument("max_distance_m must be >= 0");
}

}  // namespace

RayHit CollisionWorld::ray_cast(const Vec3& origin, const Vec3& direction_unit,
                                double max_distance_m, int ignore_handle, int mask) const {
  // One traversal stack per thread: Bullet's own broadphase ray test shares a member stack,
  // which would race once the binding releases the GIL.
  thread_local btAlignedObjectArray<const btDbvtNode*> stack;
  const btVector3 from = to_bt(origin);
  const btVector3 direction = to_bt(direction_unit);
  btVector3 inverse;
  unsigned int signs[3];
  for (int axis = 0; axis < 3; ++axis) {
    inverse[axis] = direction[axis] == 0.0 ? BT_LARGE_FLOAT : 1.0 / direction[axis];
    signs[axis] = inverse[axis] < 0.0;
  }
  const btVector3 to = from + direction * max_distance_m;
  const btVector3 zero(0, 0, 0);
  RayHit best = no_hit(max_distance_m);
  RayCollector collector(from, direction, ignore_handle, mask, best);
  for (const btDbvt& tree : broadphase_->m_sets) {
    tree.rayTestInternal(tree.m_root, from, to, inverse, signs, max_distance_m, zero, zero,
                         stack, collector);
  }
  return finished(best);
}

RayCastBatch CollisionWorld::ray_cast(const Eigen::Ref<const RowMatrixXd>& origins,
                                      const Eigen::Ref<const RowMatrixXd>& directions,
                                      double max_distance_m, int ignore_handle, int mask) const {
  check_rays(origins, directions, max_distance_m);
  const Eigen::Index count = origins.rows();
  RayCastBatch out{VectorXd(count), VectorXi(count), RowMatrixXd(count, 3)};
  for (Eigen::Index i = 0; i < count; ++i) {
    const Vec3 direction = directions.row(i).transpose().normalized();
    const RayHit hit =
        ray_cast(origins.row(i).transpose(), direction, max_distance_m, ignore_handle, mask);
    out.distance_m[i] = hit.distance_m;
    out.handle[i] = hit.handle;
    out.normal.row(i) = hit.normal.transpose();
  }
  return out;
}

void CollisionWorld::overlap_query(const Vec3& aabb_min, const Vec3& aabb_max, int mask,
                                   int ignore_handle, std::vector<const Body*>& out) const {
  const std::size_t first = out.size();
  BoxCollector collector(mask, ignore_handle, out);
  broadphase_->aabbTest(to_bt(aabb_min), to_bt(aabb_max), collector);
  // Handle order, not tree order: ties between equally close objects then resolve the same way
  // in a replay after a reset, whatever the tree looks like by then.
  std::sort(out.begin() + first, out.end(),
            [](const Body* a, const Body* b) { return a->handle < b->handle; });
}

BoundingSphere CollisionWorld::bounding_sphere(const Body& body) {
  const Primitive& shape = body.primitive;
  double radius_m = shape.radius_m;
  if (shape.kind == Primitive::Kind::kBox) radius_m = shape.half_extents.length();
  if (shape.kind == Primitive::Kind::kCylinder) radius_m = std::hypot(radius_m, shape.half_height_m);
  return {to_eigen(body.object->getWorldTransform().getOrigin()), radius_m};
}

RayHit CollisionWorld::ray_cast_bodies(const std::vector<const Body*>& bodies, const Vec3& origin,
                                       const Vec3& direction_unit, double max_distance_m) {
  const btVector3 from = to_bt(origin);
  const btVector3 direction = to_bt(direction_unit);
  RayHit best = no_hit(max_distance_m);
  for (const Body* body : bodies) {
    test_body(*body, body->object->getWorldTransform().invXform(from), direction, best);
  }
  return finished(best);
}

RayTarget ray_target(const Body& body, const Vec3& origin) {
  const btVector3 local_origin = body.object->getWorldTransform().invXform(to_bt(origin));
  // Shrunk by far more than the rounding of either this distance or a ray's hit parameter,
  // both computed from the same local origin.
  const btVector3 magnitude = local_origin.absolute();
  const double rounding_m = 1e-9 * (1.0 + magnitude[magnitude.maxAxis()]);
  return RayTarget{&body, local_origin,
                   distance_to_primitive(body.primitive, local_origin) - rounding_m};
}

RayHit ray_cast_targets(const std::vector<RayTarget>& targets, const Vec3& direction_unit,
                        double max_distance_m) {
  const btVector3 direction = to_bt(direction_unit);
  RayHit best = no_hit(max_distance_m);
  for (const RayTarget& target : targets) {
    // Every hit on this body lies beyond the reach left: test_body would refuse it.
    if (target.min_distance_m > best.distance_m) continue;
    test_body(*target.body, target.local_origin, direction, best);
  }
  return finished(best);
}

}  // namespace evc
