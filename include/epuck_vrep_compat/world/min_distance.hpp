/// @file
/// Minimum distance between convex objects: the closest points of two objects of a
/// CollisionWorld, or of shapes given by value (a tracked operator's body, placed where a
/// tracker believes it is) against objects of the world.
///
/// Bullet's GJK (btGjkPairDetector) finds the closest points of two convex shapes; when they
/// overlap, EPA finds the penetration depth and the distance is its negative. The shapes are
/// queried with zero collision margin, so boxes keep their sharp edges and corners: the answer
/// is the distance between the exact primitives, to GJK's tolerance (about 1e-6 relative).
///
///     d(A, B) = min |a - b| over a in A, b in B     (A, B apart)
///     d(A, B) = -(penetration depth)                (A, B overlapping)
#pragma once

#include <vector>

#include "epuck_vrep_compat/world/collision_world.hpp"
#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

/// A convex shape by value, centred at its pose's origin; cylinder and capsule axes are local z.
struct ConvexShape {
  enum class Kind { kBox, kCylinder, kSphere, kCapsule };
  Kind kind = Kind::kSphere;
  Vec3 half_extents_m = Vec3::Zero();  ///< box only
  double radius_m = 0.0;               ///< cylinder, sphere, capsule
  double half_height_m = 0.0;          ///< cylinder: half its height; capsule: half its segment

  /// Throws std::invalid_argument for sizes outside (0, kWorldLimit_m] (a capsule's segment
  /// may be 0: a sphere).
  static ConvexShape box(const Vec3& half_extents_m);
  static ConvexShape cylinder(double radius_m, double height_m);
  static ConvexShape sphere(double radius_m);
  /// A segment of @p segment_m along z, swept by a ball of @p radius_m.
  static ConvexShape capsule(double radius_m, double segment_m);
};

/// The closest points of two objects A and B, world frame.
struct ClosestPoints {
  double distance_m = 0.0;     ///< > 0 apart, 0 touching, < 0 minus the penetration depth
  Vec3 point_a_m = Vec3::Zero();  ///< on A's surface
  Vec3 point_b_m = Vec3::Zero();  ///< on B's surface
};

/// Closest points of two shapes at two poses (poses checked as the world checks them).
ClosestPoints closest_points(const ConvexShape& a, const Pose& pose_a, const ConvexShape& b,
                             const Pose& pose_b);
/// Closest points of two objects of @p world. Throws UnknownHandle.
ClosestPoints closest_points(const CollisionWorld& world, int handle_a, int handle_b);

/// For each of @p groups groups of B objects, the closest pair between any A and any B object
/// of the group; row g of every field is group g. A group without objects has distance +inf,
/// handles -1 and zero points.
struct MinimumDistances {
  VectorXd distance_m;
  RowMatrixXd point_a_m;   ///< (groups, 3)
  RowMatrixXd point_b_m;   ///< (groups, 3)
  VectorXi index_a;        ///< which A (its index in the A list), -1 for none
  VectorXi handle_b;       ///< which B object, -1 for none
};

/// A objects given by handle. Throws UnknownHandle, std::invalid_argument for lists of
/// different lengths or a group outside [0, groups).
MinimumDistances minimum_distances(const CollisionWorld& world, const std::vector<int>& handles_a,
                                   const std::vector<int>& handles_b,
                                   const std::vector<int>& group_of_b, int groups);
/// A objects given by value (shapes at poses), against objects of the world.
MinimumDistances minimum_distances(const CollisionWorld& world,
                                   const std::vector<ConvexShape>& shapes_a,
                                   const std::vector<Pose>& poses_a,
                                   const std::vector<int>& handles_b,
                                   const std::vector<int>& group_of_b, int groups);

}  // namespace evc
