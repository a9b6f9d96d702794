// Minimum distance in epuck_vrep_compat._core: ConvexShape, closest_points of two shapes, and
// CollisionWorld.closest_points / minimum_distances. A thin shim like cell_bindings.cpp.
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding_helpers.hpp"
#include "epuck_vrep_compat/world/min_distance.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace evc {
namespace {

using bindings::MatrixRef;
using bindings::pose_of;
using bindings::vec3;
using bindings::VectorRef;

py::tuple as_tuple(const ClosestPoints& c) {
  return py::make_tuple(c.distance_m, c.point_a_m, c.point_b_m);
}

py::tuple as_tuple(MinimumDistances&& d) {
  return py::make_tuple(std::move(d.distance_m), std::move(d.point_a_m),
                        std::move(d.point_b_m), std::move(d.index_a), std::move(d.handle_b));
}

std::vector<Pose> poses_of(const MatrixRef& positions, const MatrixRef& quaternions) {
  if (positions.cols() != 3 || quaternions.cols() != 4 ||
      quaternions.rows() != positions.rows()) {
    throw std::invalid_argument("positions must have shape (M, 3) and quaternions (M, 4)");
  }
  std::vector<Pose> poses;
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const auto q = quaternions.row(i);
    poses.push_back(Pose{positions.row(i).transpose(), Quat(q[3], q[0], q[1], q[2])});
  }
  return poses;
}

void bind_shape(py::module_& m) {
  py::class_<ConvexShape> shape(
      m, "ConvexShape",
      "A convex shape by value, centred at its pose; cylinder and capsule axes along local z. "
      "Built by box, cylinder, sphere or capsule (ValueError for sizes outside (0, 1e6] m).");
  shape.def_static("box", [](const VectorRef& h) { return ConvexShape::box(vec3(h, "half_extents")); },
                   "half_extents"_a, "A box of half extents (3,) m.")
      .def_static("cylinder", &ConvexShape::cylinder, "radius"_a, "height"_a,
                  "A cylinder of radius and height, m.")
      .def_static("sphere", &ConvexShape::sphere, "radius"_a, "A sphere, m.")
      .def_static("capsule", &ConvexShape::capsule, "radius"_a, "segment"_a,
                  "A segment of length segment along z swept by a ball of radius, m.")
      .def_property_readonly("kind", [](const ConvexShape& s) {
        static const char* names[] = {"box", "cylinder", "sphere", "capsule"};
        return std::string(names[static_cast<int>(s.kind)]); }, "box, cylinder, sphere or capsule.");
  m.def(
      "closest_points",
      [](const ConvexShape& a, const VectorRef& pa, const VectorRef& qa, const ConvexShape& b,
         const VectorRef& pb, const VectorRef& qb) {
        return as_tuple(closest_points(a, pose_of(pa, qa), b, pose_of(pb, qb)));
      },
      "shape_a"_a, "position_a"_a, "quaternion_a"_a, "shape_b"_a, "position_b"_a,
      "quaternion_b"_a,
      "Closest points of two shapes at poses (position (3,), quaternion (4,) x, y, z, w). "
      "Returns (distance m: < 0 is minus the penetration depth, point on A (3,), point on B "
      "(3,)), world frame.");
}

void bind_world_distances(py::module_& m) {
  auto world = py::reinterpret_borrow<py::class_<CollisionWorld>>(m.attr("CollisionWorld"));
  world.def(
      "closest_points",
      [](const CollisionWorld& w, int a, int b) { return as_tuple(closest_points(w, a, b)); },
      "handle_a"_a, "handle_b"_a,
      "Closest points of two objects: (distance m, < 0 overlapping; point on A (3,); point "
      "on B (3,)). KeyError for an unknown handle.");
  world.def(
      "minimum_distances",
      [](const CollisionWorld& w, const std::vector<int>& handles_a,
         const std::vector<int>& handles_b, const std::vector<int>& group_of_b, int groups) {
        py::gil_scoped_release release;
        MinimumDistances d = minimum_distances(w, handles_a, handles_b, group_of_b, groups);
        py::gil_scoped_acquire acquire;
        return as_tuple(std::move(d));
      },
      "handles_a"_a, "handles_b"_a, "group_of_b"_a, "groups"_a,
      "Per group g of B objects (group_of_b[j] in [0, groups)), the closest pair between any "
      "A object and the group's B objects. Returns (distance (groups,) m, +inf for an empty "
      "group, NaN if unknown; point on A (groups, 3); point on B (groups, 3); index of the A "
      "object (groups,), -1 for none; handle of the B object (groups,), -1 for none).");
  world.def(
      "minimum_distances_to",
      [](const CollisionWorld& w, const std::vector<ConvexShape>& shapes,
         const MatrixRef& positions, const MatrixRef& quaternions,
         const std::vector<int>& handles_b, const std::vector<int>& group_of_b, int groups) {
        const std::vector<Pose> poses = poses_of(positions, quaternions);
        py::gil_scoped_release release;
        MinimumDistances d = minimum_distances(w, shapes, poses, handles_b, group_of_b, groups);
        py::gil_scoped_acquire acquire;
        return as_tuple(std::move(d));
      },
      "shapes_a"_a, "positions_a"_a, "quaternions_a"_a, "handles_b"_a, "group_of_b"_a,
      "groups"_a,
      "minimum_distances with the A objects given by value: shapes (list of ConvexShape) at "
      "positions (M, 3) and quaternions (M, 4) x, y, z, w (e.g. a tracked operator's body "
      "where the tracker puts it).");
}

}  // namespace

void bind_distance(py::module_& m) {
  bind_shape(m);
  bind_world_distances(m);
}

}  // namespace evc
