// Ray casts and box queries of a CollisionWorld: Bullet's broadphase tree finds the candidate
// objects, closed-form geometry (primitive_ray) finds the exact hit. Box queries come singly
// or in batches (one tree query over the region, then a grid); in a world of a few objects
// (a learning world) a query tests every object's box and a small batch every pair instead,
// with the same answers. Rays from a shared origin can skip the objects they cannot reach
// (body.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <btBulletCollisionCommon.h>

#include "body.hpp"
#include "bullet_conversions.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Below this size a batch of box queries tests every (query, object) pair instead of building a
// grid (and below kSmallWorld a box query tests every object instead of descending the tree).
constexpr std::size_t kSmallBatch = 256;

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
  // An exact tie goes to the lower handle, whatever order the objects come in (the tree's
  // order depends on the history of moves; lists in handle order keep their first).
  if (best.handle >= 0 && (t > limit || (t == limit && body.handle > best.handle))) return;
  best.distance_m = t;
  best.handle = body.handle;
  best.normal = to_eigen(transform.getBasis() * normal);
  best.rgb = body.rgb;
}

// The point of a primitive closest to @p point, both in the primitive's frame; @p point itself
// when it is inside.
btVector3 closest_point(const Primitive& primitive, const btVector3& point) {
  btVector3 closest = point;
  switch (primitive.kind) {
    case Primitive::Kind::kBox:
      closest.setMax(-primitive.half_extents);
      closest.setMin(primitive.half_extents);
      break;
    case Primitive::Kind::kCylinder: {
      // Coordinates are within ±kWorldLimit_m, so the squares cannot overflow.
      const double radial = std::sqrt(point.x() * point.x() + point.y() * point.y());
      if (radial > primitive.radius_m) {
        closest.setX(point.x() * (primitive.radius_m / radial));
        closest.setY(point.y() * (primitive.radius_m / radial));
      }
      closest.setZ(std::clamp(point.z(), -primitive.half_height_m, primitive.half_height_m));
      break;
    }
    case Primitive::Kind::kSphere: {
      const double length = point.length();
      if (length > primitive.radius_m) closest = point * (primitive.radius_m / length);
      break;
    }
  }
  return closest;
}

// The largest coordinate or size in a primitive's frame that a computation about it meets.
double scale_of(const Primitive& primitive, const btVector3& point) {
  const btVector3 magnitude = point.absolute();
  const double size = primitive.kind == Primitive::Kind::kBox
                          ? primitive.half_extents[primitive.half_extents.maxAxis()]
                          : primitive.radius_m + primitive.half_height_m;
  return std::max(magnitude[magnitude.maxAxis()], size);
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

// The tree's leaves are the objects' boxes fattened by a margin (5 cm) so that small moves need
// no tree update; testing the object's own box too keeps a query from returning every object
// within that margin, which in a crowd is most of the neighbours.
class BoxCollector : public btBroadphaseAabbCallback {
 public:
  BoxCollector(const btVector3& aabb_min, const btVector3& aabb_max, int mask, int ignore_handle,
               std::vector<const Body*>& out)
      : min_(aabb_min), max_(aabb_max), mask_(mask), ignore_(ignore_handle), out_(out) {}

  bool process(const btBroadphaseProxy* proxy) override {
    const Body& body = body_of(proxy);
    if (body.handle != ignore_ && (body.group & mask_) != 0 &&
        TestAabbAgainstAabb2(proxy->m_aabbMin, proxy->m_aabbMax, min_, max_)) {
      out_.push_back(&body);
    }
    return true;
  }

 private:
  btVector3 min_;
  btVector3 max_;
  int mask_;
  int ignore_;
  std::vector<const Body*>& out_;
};

// An object's broadphase box, copied out of Bullet for the loops of a batched query.
struct ObjectBox {
  btVector3 min_m, max_m;
  int handle;
};

// A uniform grid over a region of the ground plane, listing which objects' boxes cover each
// cell. Cells are as wide as the widest query box, so that a query covers 4 cells at most;
// coarser if there would be more cells than 4 per box, or more than 4096 along a side.
class CellGrid {
 public:
  CellGrid(const Vec3& lowest, const Vec3& highest, double widest_m, std::size_t boxes,
           const std::vector<ObjectBox>& objects)
      : lowest_(lowest) {
    const Eigen::Array2d extent = (highest - lowest).head<2>().array();
    const double budget = 4.0 * static_cast<double>(boxes) + 16.0;
    cell_m_ = std::max(
        {widest_m, std::sqrt(extent.prod() / budget), extent.maxCoeff() / 4096.0, 1e-9});
    columns_ = static_cast<int>(extent.x() / cell_m_) + 1;
    rows_ = static_cast<int>(extent.y() / cell_m_) + 1;
    // Count the objects per cell, then place them: one array bucketed by cell.
    first_.assign(static_cast<std::size_t>(columns_) * rows_ + 1, 0);
    for (const ObjectBox& object : objects) {
      visit_cells(object.min_m, object.max_m, [&](std::size_t cell) { ++first_[cell + 1]; });
    }
    for (std::size_t cell = 1; cell < first_.size(); ++cell) first_[cell] += first_[cell - 1];
    objects_.resize(first_.back());
    std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
    for (std::uint32_t k = 0; k < objects.size(); ++k) {
      visit_cells(objects[k].min_m, objects[k].max_m,
                  [&](std::size_t cell) { objects_[next[cell]++] = k; });
    }
  }

  // Calls visit(k) for each object listed in the cells the box covers (once per cell).
  template <typename Visit>
  void visit(const btVector3& min_m, const btVector3& max_m, Visit visit) const {
    visit_cells(min_m, max_m, [&](std::size_t cell) {
      for (std::size_t i = first_[cell]; i < first_[cell + 1]; ++i) visit(objects_[i]);
    });
  }

 private:
  int index(double coordinate, double origin, int count) const {
    return std::clamp(static_cast<int>((coordinate - origin) / cell_m_), 0, count - 1);
  }

  template <typename Visit>
  void visit_cells(const btVector3& min_m, const btVector3& max_m, Visit visit) const {
    const int x0 = index(min_m.x(), lowest_.x(), columns_);
    const int x1 = index(max_m.x(), lowest_.x(), columns_);
    const int y1 = index(max_m.y(), lowest_.y(), rows_);
    for (int y = index(min_m.y(), lowest_.y(), rows_); y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) visit(static_cast<std::size_t>(y) * columns_ + x);
    }
  }

  Vec3 lowest_;
  double cell_m_ = 1.0;
  int columns_ = 1, rows_ = 1;
  std::vector<std::size_t> first_;        // cell c's objects: objects_[first_[c], first_[c + 1])
  std::vector<std::uint32_t> objects_;
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
  refresh_broadphase();
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
  refresh_broadphase();
  BoxCollector collector(to_bt(aabb_min), to_bt(aabb_max), mask, ignore_handle, out);
  if (bodies_.size() <= kSmallWorld) {
    // A few objects: testing every object's box finds what the tree descent finds (a leaf's
    // fattened box holds the object's box), for less than the descent costs.
    const btCollisionObjectArray& objects = world_->getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) collector.process(objects[i]->getBroadphaseHandle());
  } else {
    broadphase_->aabbTest(to_bt(aabb_min), to_bt(aabb_max), collector);
  }
  // Handle order, not tree order: ties between equally close objects then resolve the same way
  // in a replay after a reset, whatever the tree looks like by then.
  std::sort(out.begin() + first, out.end(),
            [](const Body* a, const Body* b) { return a->handle < b->handle; });
}

void overlap_query_batch(const CollisionWorld& world, const std::vector<BoxQuery>& queries,
                         int mask, std::vector<std::size_t>& first,
                         std::vector<const Body*>& out) {
  first.assign(queries.size() + 1, 0);
  out.clear();
  if (queries.empty()) return;
  Vec3 lowest = queries.front().min_m, highest = queries.front().max_m;
  double widest_m = 0.0;
  for (const BoxQuery& query : queries) {
    lowest = lowest.cwiseMin(query.min_m);
    highest = highest.cwiseMax(query.max_m);
    widest_m = std::max(widest_m, (query.max_m - query.min_m).head<2>().maxCoeff());
  }
  // Kept per thread from one call to the next: a step's queries allocate nothing. (Reached
  // through references: each use of a thread_local itself looks its address up.)
  thread_local std::vector<const Body*> found_kept;
  thread_local std::vector<ObjectBox> objects_kept;
  std::vector<const Body*>& found = found_kept;
  std::vector<ObjectBox>& objects = objects_kept;
  found.clear();
  objects.clear();
  world.overlap_query(lowest, highest, mask, -1, found);
  for (const Body* body : found) {
    const btBroadphaseProxy* proxy = body->object->getBroadphaseHandle();
    objects.push_back(ObjectBox{proxy->m_aabbMin, proxy->m_aabbMax, body->handle});
  }
  if (queries.size() * objects.size() <= kSmallBatch) {
    // Few pairs: each query tests every object, in handle order (found's), without a grid.
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const BoxQuery& query = queries[q];
      const btVector3 query_min = to_bt(query.min_m), query_max = to_bt(query.max_m);
      for (std::size_t k = 0; k < objects.size(); ++k) {
        const ObjectBox& object = objects[k];
        if (object.handle != query.ignore_handle &&
            TestAabbAgainstAabb2(object.min_m, object.max_m, query_min, query_max)) {
          out.push_back(found[k]);
        }
      }
      first[q + 1] = out.size();
    }
    return;
  }
  const CellGrid grid(lowest, highest, widest_m, queries.size() + objects.size(), objects);
  // Each query meets the objects of its cells, each object once, and tests their boxes as
  // overlap_query does.
  std::vector<std::size_t> seen_by(objects.size(), 0);  // 1 + the last query to meet it
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const BoxQuery& query = queries[q];
    const btVector3 query_min = to_bt(query.min_m), query_max = to_bt(query.max_m);
    const std::size_t begin = out.size();
    grid.visit(query_min, query_max, [&](std::uint32_t k) {
      if (seen_by[k] == q + 1) return;
      seen_by[k] = q + 1;
      const ObjectBox& object = objects[k];
      if (object.handle != query.ignore_handle &&
          TestAabbAgainstAabb2(object.min_m, object.max_m, query_min, query_max)) {
        out.push_back(found[k]);
      }
    });
    std::sort(out.begin() + begin, out.end(),
              [](const Body* a, const Body* b) { return a->handle < b->handle; });
    first[q + 1] = out.size();
  }
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
  const btTransform& transform = body.object->getWorldTransform();
  const btVector3 local_origin = transform.invXform(to_bt(origin));
  const btVector3 offset = closest_point(body.primitive, local_origin) - local_origin;
  const double length_m = offset.length();
  // Shrunk by far more than the rounding of this distance, of the separating plane and of a
  // ray's hit parameter, all computed from the same local origin.
  const double rounding_m = 1e-9 * (1.0 + scale_of(body.primitive, local_origin));
  RayTarget target{&body, local_origin, btVector3(0, 0, 0), length_m - rounding_m};
  if (target.min_distance_m > 0.0) target.toward = transform.getBasis() * (offset / length_m);
  return target;
}

RayHit ray_cast_targets(const std::vector<RayTarget>& targets, const Vec3& direction_unit,
                        double max_distance_m) {
  const btVector3 direction = to_bt(direction_unit);
  RayHit best = no_hit(max_distance_m);
  for (const RayTarget& target : targets) {
    // The body lies beyond the plane through its closest point square to `toward`, so a hit
    // at t has t (d · toward) >= min_distance_m: when even the reach left falls short of that,
    // test_body would refuse the hit. Rays leaving the plane behind (d · toward <= 0) miss.
    if (target.min_distance_m > best.distance_m * direction.dot(target.toward)) continue;
    test_body(*target.body, target.local_origin, direction, best);
  }
  return finished(best);
}

}  // namespace evc
