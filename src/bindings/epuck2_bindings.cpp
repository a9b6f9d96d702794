// The e-puck2's extra sensors computed in the core: the time-of-flight distance sensor.
#include <cstdint>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding_helpers.hpp"
#include "epuck_vrep_compat/epuck/tof_sensor.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace evc {

void bind_epuck2(py::module_& m) {
  using bindings::MatrixRef;
  using bindings::VectorRef;
  const TofSpec defaults;
  py::class_<TofSensorArray>(
      m, "TofSensorArray",
      "One VL53L0X time-of-flight sensor per robot: the distance along its pitched axis to the "
      "first surface, noise SD stddev_m + stddev_rel d from each robot's own stream, clamped to "
      "[min, max]; max where nothing is within max (see tof_sensor.hpp).")
      .def(py::init([](const VectorRef& mount_m, double pitch_rad, double min_range_m,
                       double max_range_m, double stddev_m, double stddev_rel,
                       std::uint64_t seed) {
             TofSpec spec;
             spec.mount_m = bindings::vec3(mount_m, "mount_m");
             spec.pitch_rad = pitch_rad;
             spec.min_range_m = min_range_m;
             spec.max_range_m = max_range_m;
             spec.stddev_m = stddev_m;
             spec.stddev_rel = stddev_rel;
             return TofSensorArray(spec, seed);
           }),
           "mount_m"_a = VectorXd(defaults.mount_m), "pitch_rad"_a = defaults.pitch_rad,
           "min_range_m"_a = defaults.min_range_m, "max_range_m"_a = defaults.max_range_m,
           "stddev_m"_a = defaults.stddev_m, "stddev_rel"_a = defaults.stddev_rel,
           "seed"_a = 0,
           "Mount (3,) body frame m, pitch about body y (negative looks up), range m, noise. "
           "ValueError for an unusable spec.")
      .def(
          "read",
          [](TofSensorArray& a, const CollisionWorld& world, const MatrixRef& planar_poses,
             const std::vector<int>& body_handles, const std::vector<std::uint64_t>& robot_ids,
             bool noise) {
            VectorXd out;
            {
              py::gil_scoped_release release;
              out = a.read(world, planar_poses, body_handles, robot_ids, noise);
            }
            return out;
          },
          "world"_a, "planar_poses"_a, "body_handles"_a, "robot_ids"_a, "noise"_a = true,
          "Ranges (N,) m of N robots at planar poses (N, 3) x, y, yaw; body_handles (N,) "
          "their own bodies (not seen); robot_ids (N,) stable ids keying the noise streams.")
      .def("reseed", &TofSensorArray::reseed, "seed"_a,
           "Restarts every robot's noise stream from seed.");
}

}  // namespace evc
