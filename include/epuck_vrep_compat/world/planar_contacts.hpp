/// @file
/// Exact penetration of an upright cylinder into an upright cylinder or an upright box: the
/// closed-form narrowphase of contact resolution (body_contacts.hpp) for the shapes an e-puck
/// world is built of.
///
/// Both shapes are vertical prisms: a convex figure in the ground plane (a circle, a rectangle
/// of any yaw) swept over a height interval [z_min, z_max]. Robots move in the plane only, so
/// two prisms whose height intervals overlap (touching is not overlapping) meet as their plane
/// figures do, and the contact is planar:
///  - circle (c, r) and circle (c', r'): depth r + r' - |c - c'|, normal (c - c') / |c - c'|,
///    or +x when the centres coincide;
///  - circle and rectangle: with p the circle's centre in the rectangle's frame and q the
///    point of the rectangle closest to p, outside (p != q) depth r - |p - q|, normal
///    (p - q) / |p - q|; inside, depth r + the distance to the nearest side, normal that
///    side's outward normal (the x sides on a tie), so the circle leaves through the nearest
///    face however deep it is.
///
/// Depths are metres, > 0 for a contact (touching is none); normals are unit, world frame, in
/// the ground plane, pointing from the other shape towards the circle.
#pragma once

#include <optional>

#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

/// An upright cylinder: a disc in the ground plane swept over [z_min_m, z_max_m].
struct UprightCircle {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
  double z_min_m = 0.0;
  double z_max_m = 0.0;
};

/// An upright box: a rectangle in the ground plane swept over [z_min_m, z_max_m].
struct UprightRectangle {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis_x = Eigen::Vector2d::UnitX();  ///< unit, the box's local x in the plane
  Eigen::Vector2d axis_y = Eigen::Vector2d::UnitY();  ///< unit, the box's local y in the plane
  Eigen::Vector2d half_extents_m = Eigen::Vector2d::Zero();  ///< along axis_x, axis_y
  double z_min_m = 0.0;
  double z_max_m = 0.0;
};

/// Where a circle stands in the plane relative to another figure.
struct PlanarSeparation {
  Eigen::Vector2d normal;  ///< unit, from the other figure towards the circle
  double distance_m;       ///< gap between the figures; negative: minus the depth of overlap
};

/// Signed planar distance from the circle @p self to the circle @p other (heights ignored).
PlanarSeparation planar_separation(const UprightCircle& self, const UprightCircle& other);
/// Signed planar distance from the circle @p self to the rectangle @p other (heights ignored).
PlanarSeparation planar_separation(const UprightCircle& self, const UprightRectangle& other);

/// How deep a circle sinks into another shape, and which way it leaves.
struct Penetration {
  Vec3 normal;     ///< unit, world frame, horizontal, from the other shape towards the circle
  double depth_m;  ///< > 0
};

/// Penetration of @p self into @p other, or nothing when their figures or heights do not
/// overlap.
std::optional<Penetration> penetration(const UprightCircle& self, const UprightCircle& other);
/// Penetration of @p self into @p other, or nothing when their figures or heights do not
/// overlap.
std::optional<Penetration> penetration(const UprightCircle& self, const UprightRectangle& other);

}  // namespace evc
