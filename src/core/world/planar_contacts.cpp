#include "epuck_vrep_compat/world/planar_contacts.hpp"

#include <algorithm>
#include <cmath>

namespace evc {
namespace {

// The planar overlap, when the heights overlap too.
template <typename Other>
std::optional<Penetration> prism_penetration(const UprightCircle& self, const Other& other) {
  if (!(self.z_min_m < other.z_max_m && other.z_min_m < self.z_max_m)) return std::nullopt;
  const PlanarSeparation planar = planar_separation(self, other);
  if (!(planar.distance_m < 0.0)) return std::nullopt;
  return Penetration{Vec3(planar.normal.x(), planar.normal.y(), 0.0), -planar.distance_m};
}

}  // namespace

PlanarSeparation planar_separation(const UprightCircle& self, const UprightCircle& other) {
  const Eigen::Vector2d offset = self.centre_m - other.centre_m;
  const double distance_m = offset.norm();
  const Eigen::Vector2d normal =
      distance_m > 0.0 ? Eigen::Vector2d(offset / distance_m) : Eigen::Vector2d::UnitX();
  return PlanarSeparation{normal, distance_m - self.radius_m - other.radius_m};
}

PlanarSeparation planar_separation(const UprightCircle& self, const UprightRectangle& other) {
  const Eigen::Vector2d offset = self.centre_m - other.centre_m;
  const Eigen::Vector2d p(offset.dot(other.axis_x), offset.dot(other.axis_y));
  const Eigen::Vector2d& half = other.half_extents_m;
  const Eigen::Vector2d outside(std::max(std::abs(p.x()) - half.x(), 0.0),
                                std::max(std::abs(p.y()) - half.y(), 0.0));
  const double sign_x = p.x() < 0.0 ? -1.0 : 1.0;
  const double sign_y = p.y() < 0.0 ? -1.0 : 1.0;
  double centre_distance_m = 0.0;  // of the circle's centre from the rectangle, < 0 inside
  Eigen::Vector2d local_normal;
  if (outside.x() > 0.0 || outside.y() > 0.0) {
    centre_distance_m = outside.norm();
    local_normal =
        Eigen::Vector2d(sign_x * outside.x(), sign_y * outside.y()) / centre_distance_m;
  } else {
    const double to_x_side_m = half.x() - std::abs(p.x());
    const double to_y_side_m = half.y() - std::abs(p.y());
    const bool x_side = to_x_side_m <= to_y_side_m;
    centre_distance_m = -(x_side ? to_x_side_m : to_y_side_m);
    local_normal = x_side ? Eigen::Vector2d(sign_x, 0.0) : Eigen::Vector2d(0.0, sign_y);
  }
  return PlanarSeparation{local_normal.x() * other.axis_x + local_normal.y() * other.axis_y,
                          centre_distance_m - self.radius_m};
}

std::optional<Penetration> penetration(const UprightCircle& self, const UprightCircle& other) {
  const double reach_m = self.radius_m + other.radius_m;
  if ((self.centre_m - other.centre_m).squaredNorm() >= reach_m * reach_m) return std::nullopt;
  return prism_penetration(self, other);
}

std::optional<Penetration> penetration(const UprightCircle& self, const UprightRectangle& other) {
  return prism_penetration(self, other);
}

}  // namespace evc
