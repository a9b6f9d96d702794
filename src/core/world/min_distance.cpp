#include "epuck_vrep_compat/world/min_distance.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <btBulletCollisionCommon.h>

#include "body.hpp"
#include "bullet_conversions.hpp"
#include "pose_checks.hpp"

namespace evc {
namespace {

void check_size(double value, const char* name, bool zero_ok = false) {
  if (!((value > 0.0 || (zero_ok && value == 0.0)) && value <= kWorldLimit_m)) {
    throw std::invalid_argument(std::string(name) + " must be in (0, 1e6] m");
  }
}

// A Bullet shape of the exact primitive: zero margin, so a box keeps its corners (Bullet's
// default margin would round them by 4 cm). A sphere and a capsule are a point and a segment
// with their radius as margin, exact as they are.
std::unique_ptr<btConvexShape> exact_shape(const ConvexShape& s) {
  std::unique_ptr<btConvexShape> shape;
  switch (s.kind) {
    case ConvexShape::Kind::kBox:
      shape = std::make_unique<btBoxShape>(to_bt(s.half_extents_m));
      break;
    case ConvexShape::Kind::kCylinder:
      shape = std::make_unique<btCylinderShapeZ>(
          btVector3(s.radius_m, s.radius_m, s.half_height_m));
      break;
    case ConvexShape::Kind::kSphere:
      return std::make_unique<btSphereShape>(s.radius_m);
    case ConvexShape::Kind::kCapsule:
      return std::make_unique<btCapsuleShapeZ>(s.radius_m, 2.0 * s.half_height_m);
  }
  shape->setMargin(0.0);
  return shape;
}

ConvexShape shape_of(const Primitive& p) {
  switch (p.kind) {
    case Primitive::Kind::kBox:
      return ConvexShape::box(to_eigen(p.half_extents));
    case Primitive::Kind::kCylinder:
      return ConvexShape::cylinder(p.radius_m, 2.0 * p.half_height_m);
    case Primitive::Kind::kSphere:
      break;
  }
  return ConvexShape::sphere(p.radius_m);
}

// One object of a query: its exact shape and where it is.
struct Placed {
  std::unique_ptr<btConvexShape> shape;
  btTransform transform;
};

Placed placed(const CollisionWorld& world, int handle) {
  const Body& body = world.body(handle);
  return Placed{exact_shape(shape_of(body.primitive)), body.object->getWorldTransform()};
}

ClosestPoints gjk(const Placed& a, const Placed& b) {
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  btGjkPairDetector detector(a.shape.get(), b.shape.get(), &simplex, &epa);
  btGjkPairDetector::ClosestPointInput input;
  input.m_transformA = a.transform;
  input.m_transformB = b.transform;
  btPointCollector out;
  detector.getClosestPoints(input, out, nullptr);
  ClosestPoints result;
  if (!out.m_hasResult) {  // GJK failed to converge: report the centres, distance unknown
    result.distance_m = std::numeric_limits<double>::quiet_NaN();
    result.point_a_m = to_eigen(a.transform.getOrigin());
    result.point_b_m = to_eigen(b.transform.getOrigin());
    return result;
  }
  // Bullet: the point is on B, the normal points from B to A, distance < 0 when overlapping.
  result.distance_m = out.m_distance;
  result.point_b_m = to_eigen(out.m_pointInWorld);
  result.point_a_m = to_eigen(out.m_pointInWorld + out.m_normalOnBInWorld * out.m_distance);
  return result;
}

MinimumDistances nearest(const std::vector<Placed>& a, const CollisionWorld& world,
                         const std::vector<int>& handles_b, const std::vector<int>& group_of_b,
                         int groups) {
  if (handles_b.size() != group_of_b.size()) {
    throw std::invalid_argument("handles_b and group_of_b must have the same length");
  }
  if (groups < 0) throw std::invalid_argument("groups must be >= 0");
  for (std::size_t i = 0; i < group_of_b.size(); ++i) {
    if (group_of_b[i] < 0 || group_of_b[i] >= groups) {
      throw std::invalid_argument("group_of_b[" + std::to_string(i) + "] must be in [0, groups)");
    }
  }
  MinimumDistances out;
  out.distance_m = VectorXd::Constant(groups, std::numeric_limits<double>::infinity());
  out.point_a_m = RowMatrixXd::Zero(groups, 3);
  out.point_b_m = RowMatrixXd::Zero(groups, 3);
  out.index_a = VectorXi::Constant(groups, -1);
  out.handle_b = VectorXi::Constant(groups, -1);
  for (std::size_t j = 0; j < handles_b.size(); ++j) {
    const Placed b = placed(world, handles_b[j]);
    const int g = group_of_b[j];
    for (std::size_t i = 0; i < a.size(); ++i) {
      const ClosestPoints c = gjk(a[i], b);
      // NaN (no answer) wins over any number: a caller must not trust an unknown distance
      if (!(c.distance_m >= out.distance_m[g]) && !std::isnan(out.distance_m[g])) {
        out.distance_m[g] = c.distance_m;
        out.point_a_m.row(g) = c.point_a_m.transpose();
        out.point_b_m.row(g) = c.point_b_m.transpose();
        out.index_a[g] = static_cast<int>(i);
        out.handle_b[g] = handles_b[j];
      }
    }
  }
  return out;
}

}  // namespace

ConvexShape ConvexShape::box(const Vec3& half_extents_m) {
  for (int axis = 0; axis < 3; ++axis) check_size(half_extents_m[axis], "half_extents");
  ConvexShape s;
  s.kind = Kind::kBox;
  s.half_extents_m = half_extents_m;
  return s;
}

ConvexShape ConvexShape::cylinder(double radius_m, double height_m) {
  check_size(radius_m, "radius");
  check_size(height_m, "height");
  ConvexShape s;
  s.kind = Kind::kCylinder;
  s.radius_m = radius_m;
  s.half_height_m = 0.5 * height_m;
  return s;
}

ConvexShape ConvexShape::sphere(double radius_m) {
  check_size(radius_m, "radius");
  ConvexShape s;
  s.kind = Kind::kSphere;
  s.radius_m = radius_m;
  return s;
}

ConvexShape ConvexShape::capsule(double radius_m, double segment_m) {
  check_size(radius_m, "radius");
  check_size(segment_m, "segment", true);
  ConvexShape s;
  s.kind = Kind::kCapsule;
  s.radius_m = radius_m;
  s.half_height_m = 0.5 * segment_m;
  return s;
}

ClosestPoints closest_points(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b,
                             const Pose& pose_b) {
  return gjk(Placed{exact_shape(a), to_bt(checked_pose(pose_a))},
             Placed{exact_shape(b), to_bt(checked_pose(pose_b))});
}

ClosestPoints closest_points(const CollisionWorld& world, int handle_a, int handle_b) {
  return gjk(placed(world, handle_a), placed(world, handle_b));
}

MinimumDistances minimum_distances(const CollisionWorld& world, const std::vector<int>& handles_a,
                                   const std::vector<int>& handles_b,
                                   const std::vector<int>& group_of_b, int groups) {
  std::vector<Placed> a;
  a.reserve(handles_a.size());
  for (int handle : handles_a) a.push_back(placed(world, handle));
  return nearest(a, world, handles_b, group_of_b, groups);
}

MinimumDistances minimum_distances(const CollisionWorld& world,
                                   const std::vector<ConvexShape>& shapes_a,
                                   const std::vector<Pose>& poses_a,
                                   const std::vector<int>& handles_b,
                                   const std::vector<int>& group_of_b, int groups) {
  if (shapes_a.size() != poses_a.size()) {
    throw std::invalid_argument("shapes_a and poses_a must have the same length");
  }
  std::vector<Placed> a;
  a.reserve(shapes_a.size());
  for (std::size_t i = 0; i < shapes_a.size(); ++i) {
    a.push_back(Placed{exact_shape(shapes_a[i]), to_bt(checked_pose_at(poses_a, i, "poses_a"))});
  }
  return nearest(a, world, handles_b, group_of_b, groups);
}

}  // namespace evc
