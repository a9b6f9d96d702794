// BatchedWorlds: B worlds of R e-pucks stepped in one call without the GIL, for the learning
// environments. Outputs are copies of the core's buffers, so an array a caller keeps is never
// changed by a later step.
#include <cstdint>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding_helpers.hpp"
#include "epuck_vrep_compat/epuck/batched_worlds.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace evc {

void bind_batched(py::module_& m) {
  using bindings::MatrixRef;
  using bindings::vec3;
  using bindings::VectorRef;
  py::class_<BatchedWorlds> batched(
      m, "BatchedWorlds",
      "B independent worlds of R e-pucks each (own obstacles, robots, noise streams, seed), "
      "stepped in one call without the GIL. Every per-robot array has N = B * R rows, row "
      "world * R + robot. A world gives exactly the arrays of a standalone EpuckSwarm on a "
      "CollisionWorld with the same obstacles (handles 0, 1, ... in the order added), robot r "
      "under handle ROBOT_HANDLE_BASE + r, the same seed and commands. Output properties are "
      "copies (fresh arrays), filled in C++ by the step.");
  bindings::bind_noise_setters(batched,
                               "IR noise per robot and sensor, each (N, K); all or nothing.");
  batched
      .def(py::init<const EpuckModel&, int, int, const std::vector<std::uint64_t>&>(),
           "model"_a, "worlds"_a, "robots"_a, "seeds"_a,
           "worlds x robots e-pucks, world b seeded with seeds[b]; robots start on a 10 cm grid "
           "about the origin, heading 0, noise off. ValueError for bad counts or seeds.")
      .def_readonly_static("ROBOT_HANDLE_BASE", &BatchedWorlds::kRobotHandleBase,
                           "Body handle of robot 0 in each world (robot r: base + r).")
      .def_property_readonly("worlds", &BatchedWorlds::worlds, "Number of worlds, B.")
      .def_property_readonly("robots", &BatchedWorlds::robots, "Robots per world, R.")
      .def_property_readonly("size", &BatchedWorlds::size, "Robots in all, N = B * R.")
      .def_property_readonly("sensor_count", &BatchedWorlds::sensor_count,
                             "IR sensors per robot, K.")
      .def_property_readonly("frames", &BatchedWorlds::frames,
                             "(B,) int64 steps of each world since it was built or reset.")
      .def(
          "add_box",
          [](BatchedWorlds& b, int world, const VectorRef& center, const VectorRef& half_extents,
             double yaw, const VectorRef& rgb) {
            return b.add_box(world, vec3(center, "center"), vec3(half_extents, "half_extents"),
                             yaw, vec3(rgb, "rgb"));
          },
          "world"_a, "center"_a, "half_extents"_a, "yaw"_a = 0.0,
          "rgb"_a = VectorXd(kObstacleRgb),
          "Adds a static box (group STATIC) centred at center (3,), half extents (3,) in m, "
          "turned by yaw about z; returns its handle in that world.")
      .def(
          "add_cylinder",
          [](BatchedWorlds& b, int world, const VectorRef& center, double radius, double height,
             const VectorRef& rgb) {
            return b.add_cylinder(world, vec3(center, "center"), radius, height,
                                  vec3(rgb, "rgb"));
          },
          "world"_a, "center"_a, "radius"_a, "height"_a, "rgb"_a = VectorXd(kObstacleRgb),
          "Adds a static upright cylinder centred at center (3,); returns its handle.")
      .def("clear_obstacles", &BatchedWorlds::clear_obstacles, "world"_a,
           "Removes every obstacle of a world; handles start from 0 again.")
      .def("set_pose", &BatchedWorlds::set_pose, "world"_a, "robot"_a, "x"_a, "y"_a, "yaw"_a,
           "Teleports a robot, odometry too, and clears its velocity history.")
      .def("reset_world", &BatchedWorlds::reset_world, "world"_a, "seed"_a,
           "Starts one world over: frame 0, noise streams from seed, velocities and readings "
           "cleared; poses, obstacles and noise settings stay (set poses with set_pose).")
      .def("step", &BatchedWorlds::step, "dt_s"_a, "wheel_cmd"_a,
           py::call_guard<py::gil_scoped_release>(),
           "Steps every world once by dt_s with wheel commands (N, 2) = (left, right) rad/s "
           "(float64, C order avoids a copy). ValueError, before anything moves, for a bad "
           "dt_s, shape or a non-finite command.")
      .def_property_readonly("poses", &BatchedWorlds::poses, py::return_value_policy::copy, "(N, 3) x, y, yaw ground truth.")
      .def_property_readonly("velocities", &BatchedWorlds::velocities, py::return_value_policy::copy,
                             "(N, 3) vx, vy (world), yaw rate.")
      .def_property_readonly("wheel_speeds", &BatchedWorlds::wheel_speeds, py::return_value_policy::copy,
                             "(N, 2) applied wheel speeds, rad/s.")
      .def_property_readonly("odometry", &BatchedWorlds::odometry, py::return_value_policy::copy, "(N, 5) x, y, yaw, v, w.")
      .def_property_readonly("ranges", &BatchedWorlds::ranges, py::return_value_policy::copy, "(N, K) noisy IR readings, m.")
      .def_property_readonly("ranges_clean", &BatchedWorlds::ranges_clean, py::return_value_policy::copy,
                             "(N, K) clean IR readings, m (max_range_m for nothing).")
      .def_property_readonly("accel", &BatchedWorlds::accel, py::return_value_policy::copy, "(N, 3) specific force, m/s^2.")
      .def_property_readonly("gyro", &BatchedWorlds::gyro, py::return_value_policy::copy, "(N, 3) angular velocity, rad/s.")
      .def_property_readonly("in_contact", &BatchedWorlds::in_contact, py::return_value_policy::copy,
                             "(N,) bool: the robot touched an obstacle or another robot during "
                             "the last step.")
      .def("collision_world", &BatchedWorlds::collision_world, "world"_a,
           py::return_value_policy::reference_internal,
           "World b's CollisionWorld, for queries and rendering (read only: change it through "
           "this object).")
      .def("swarm", &BatchedWorlds::swarm, "world"_a, py::return_value_policy::reference_internal,
           "World b's EpuckSwarm, for its other outputs (read only: step it through this "
           "object).");
}

}  // namespace evc
