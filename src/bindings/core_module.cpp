// epuck_vrep_compat._core: a thin pybind11 shim over the C++ core (include/epuck_vrep_compat).
// It converts arguments, names the bad ones, releases the GIL around heavy work and turns C++
// exceptions into Python ones; all behaviour lives in the core.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding_helpers.hpp"
#include "epuck_vrep_compat/epuck/cone_sensor.hpp"
#include "epuck_vrep_compat/epuck/epuck_model.hpp"
#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"
#include "epuck_vrep_compat/epuck/range_noise.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/render/ray_camera.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace evc {
namespace {

using bindings::float_image_out;
using bindings::MatrixRef;
using bindings::pose_of;
using bindings::vec3;
using bindings::VectorRef;

py::tuple pose_tuple(const Pose& pose) {
  const Quat& q = pose.orientation;
  return py::make_tuple(VectorXd(pose.position_m), Eigen::Vector4d(q.x(), q.y(), q.z(), q.w()));
}

py::array per_sensor_3d(const RowMatrixXd& rows, const EpuckSwarm& swarm) {
  return py::array(py::cast(rows)).reshape({swarm.size(), swarm.sensor_count(), 3});
}

// render_into straight into new numpy arrays (no copy): (rgb or None, depth or None).
py::tuple render_arrays(const CollisionWorld& w, const VectorRef& position,
                        const VectorRef& quaternion, const CameraSpec& spec, int ignore_handle,
                        int mask, bool want_rgb, bool want_depth,
                        const py::object& depth_into = py::none()) {
  const Pose pose = pose_of(position, quaternion);
  const py::ssize_t height = std::max(spec.height, 0), width = std::max(spec.width, 0);
  py::object rgb = py::none(), depth = py::none();
  std::uint8_t* rgb_out = nullptr;
  float* depth_out = nullptr;
  if (want_rgb) {
    py::array_t<std::uint8_t> array({height, width, py::ssize_t{3}});
    rgb_out = array.mutable_data();
    rgb = std::move(array);
  }
  if (want_depth) {
    py::array_t<float> array = depth_into.is_none() ? py::array_t<float>({height, width})
                                                    : float_image_out(depth_into, height, width);
    depth_out = array.mutable_data();
    depth = std::move(array);
  }
  {
    py::gil_scoped_release release;
    render_into(w, pose, spec, ignore_handle, mask, rgb_out, depth_out);
  }
  return py::make_tuple(rgb, depth);
}

void bind_noise(py::module_& m) {
  py::class_<Rng>(m, "Rng", "Seeded xoshiro256** generator (splitmix64 seeding); the core's "
                            "only randomness, reproducible bit for bit.")
      .def(py::init<std::uint64_t>(), "seed"_a, "Seeds the generator (any non-negative int).")
      .def("uniform", &Rng::uniform, "A uniform draw in (0, 1] (top 53 bits).")
      .def("normal", &Rng::normal,
           "A standard normal: sqrt(-2 ln U1) cos(2 pi U2), two uniforms per draw.")
      .def("state_digest", &Rng::state_digest, "A 64-bit digest of the state (for tests).");

  m.def(
      "apply_range_noise",
      [](const VectorRef& clean, double min_range_m, double max_range_m, double probability,
         double mean_m, double stddev_m, std::uint64_t seed) {
        NoisyRanges out = apply_range_noise(clean, min_range_m, max_range_m,
                                            RangeNoise{probability, mean_m, stddev_m}, seed);
        return py::make_tuple(std::move(out.ranges_m), std::move(out.applied));
      },
      "clean"_a, "min_range_m"_a, "max_range_m"_a, "probability"_a, "mean_m"_a, "stddev_m"_a,
      "seed"_a,
      "V-REP e-puck IR noise on readings (M,), in order with one Rng(seed). Returns "
      "(noisy (M,), applied (M,) bool). ValueError for probability outside [0, 1], negative "
      "stddev_m or non-finite values.");
}

void bind_world(py::module_& m) {
  py::class_<CollisionWorld>(m, "CollisionWorld",
                             "Bullet collision world of boxes, cylinders and spheres keyed by "
                             "int handles (>= 0), each with an RGB colour for rendering.")
      .def(py::init<>(), "An empty world.")
      .def(
          "add_box",
          [](CollisionWorld& w, int handle, const VectorRef& half_extents,
             const VectorRef& position, const VectorRef& quaternion, const VectorRef& rgb,
             int group) {
            w.add_box(handle, vec3(half_extents, "half_extents"), pose_of(position, quaternion),
                      vec3(rgb, "rgb"), group);
          },
          "handle"_a, "half_extents"_a, "position"_a, "quaternion"_a, "rgb"_a,
          "group"_a = int(kGroupStatic),
          "Adds a box (half extents in m, quaternion x,y,z,w, rgb in 0..1). ValueError for a "
          "used handle or bad values.")
      .def(
          "add_cylinder",
          [](CollisionWorld& w, int handle, double radius, double height,
             const VectorRef& position, const VectorRef& quaternion, const VectorRef& rgb,
             int group) {
            w.add_cylinder(handle, radius, height, pose_of(position, quaternion),
                           vec3(rgb, "rgb"), group);
          },
          "handle"_a, "radius"_a, "height"_a, "position"_a, "quaternion"_a, "rgb"_a,
          "group"_a = int(kGroupStatic),
          "Adds a cylinder with its axis along local z, centred at position.")
      .def(
          "add_sphere",
          [](CollisionWorld& w, int handle, double radius, const VectorRef& position,
             const VectorRef& quaternion, const VectorRef& rgb, int group) {
            w.add_sphere(handle, radius, pose_of(position, quaternion), vec3(rgb, "rgb"), group);
          },
          "handle"_a, "radius"_a, "position"_a, "quaternion"_a, "rgb"_a,
          "group"_a = int(kGroupStatic), "Adds a sphere.")
      .def(
          "set_pose",
          [](CollisionWorld& w, int handle, const VectorRef& position,
             const VectorRef& quaternion) { w.set_pose(handle, pose_of(position, quaternion)); },
          "handle"_a, "position"_a, "quaternion"_a,
          "Moves an object (quaternion x,y,z,w). KeyError for an unknown handle.")
      .def(
          "get_pose", [](const CollisionWorld& w, int handle) {
            return pose_tuple(w.get_pose(handle));
          },
          "handle"_a, "Returns (position (3,), quaternion x,y,z,w (4,)).")
      .def("remove", &CollisionWorld::remove, "handle"_a, "Removes an object.")
      .def("has", &CollisionWorld::has, "handle"_a, "True when the handle names an object.")
      .def("handles", &CollisionWorld::handles, "Every handle, ascending.")
      .def(
          "set_color",
          [](CollisionWorld& w, int handle, const VectorRef& rgb) {
            w.set_color(handle, vec3(rgb, "rgb"));
          },
          "handle"_a, "rgb"_a, "Changes an object's colour (0..1 per channel).")
      .def(
          "set_background",
          [](CollisionWorld& w, const VectorRef& rgb) { w.set_background(vec3(rgb, "rgb")); },
          "rgb"_a, "Colour where a camera ray hits nothing.")
      .def_property_readonly("revision", &CollisionWorld::revision,
                             "Changes to the geometry so far (adds, removes, moves).")
      .def(
          "ray_cast",
          [](const CollisionWorld& w, const MatrixRef& origins, const MatrixRef& directions,
             double max_distance_m, int ignore_handle, int mask) {
            RayCastBatch out = w.ray_cast(origins, directions, max_distance_m, ignore_handle,
                                          mask);
            return std::make_tuple(std::move(out.distance_m), std::move(out.handle),
                                   std::move(out.normal));
          },
          "origins"_a, "directions"_a, "max_distance_m"_a, "ignore_handle"_a = -1,
          "mask"_a = int(kGroupAll), py::call_guard<py::gil_scoped_release>(),
          "Casts rays (M, 3) from origins along directions (normalised here). Returns "
          "(distance (M,) +inf for no hit, handle (M,) int32 -1 for none, normal (M, 3) world).")
      .def(
          "render",
          [](const CollisionWorld& w, const VectorRef& position, const VectorRef& quaternion,
             int width, int height, double vertical_fov_rad, double near_m, double far_m,
             int ignore_handle, int mask, bool rgb, bool depth, const py::object& depth_out) {
            return render_arrays(w, position, quaternion,
                                 CameraSpec{width, height, vertical_fov_rad, near_m, far_m},
                                 ignore_handle, mask, rgb, depth, depth_out);
          },
          "position"_a, "quaternion"_a, "width"_a, "height"_a, "vertical_fov_rad"_a, "near_m"_a,
          "far_m"_a, "ignore_handle"_a = -1, "mask"_a = int(kGroupAll), "rgb"_a = true,
          "depth"_a = true, "depth_out"_a = py::none(),
          "Ray-cast pinhole camera (x forward, y left, z up; row 0 at the top). Returns "
          "(rgb uint8 (H, W, 3), depth float32 (H, W) along the optical axis, far_m for none); "
          "rgb=False or depth=False gives None for that image and skips its work (no shading "
          "for a depth image alone), the other image bit for bit the same. ``depth_out``: a "
          "writable float32 C-contiguous (H, W) array to render the depth into instead of a "
          "new one (returned as the depth).")
      .def(
          "render_rgb_batch",
          [](const CollisionWorld& w, const MatrixRef& positions, const MatrixRef& quaternions,
             int width, int height, double vertical_fov_rad, double near_m, double far_m,
             const std::vector<int>& ignore_handles, int mask, int threads) {
            const Eigen::Index count = positions.rows();
            if (positions.cols() != 3 || quaternions.cols() != 4 ||
                quaternions.rows() != count) {
              throw std::invalid_argument("positions (K, 3) and quaternions (K, 4) expected");
            }
            std::vector<Pose> poses;
            poses.reserve(static_cast<std::size_t>(count));
            for (Eigen::Index k = 0; k < count; ++k) {
              poses.push_back(pose_of(positions.row(k).transpose(),
                                      quaternions.row(k).transpose()));
            }
            const CameraSpec spec{width, height, vertical_fov_rad, near_m, far_m};
            py::array_t<std::uint8_t> rgb({static_cast<py::ssize_t>(count),
                                           static_cast<py::ssize_t>(std::max(height, 0)),
                                           static_cast<py::ssize_t>(std::max(width, 0)),
                                           py::ssize_t{3}});
            std::uint8_t* out = rgb.mutable_data();
            {
              py::gil_scoped_release release;
              render_rgb_batch(w, poses, ignore_handles, spec, mask, threads, out);
            }
            return rgb;
          },
          "positions"_a, "quaternions"_a, "width"_a, "height"_a, "vertical_fov_rad"_a,
          "near_m"_a, "far_m"_a, "ignore_handles"_a, "mask"_a = int(kGroupAll),
          "threads"_a = 1,
          "K cameras' colour images in one call, on up to ``threads`` threads, each as "
          "``render`` makes it (camera k does not see ignore_handles[k]). Returns rgb uint8 "
          "(K, H, W, 3).");
}

void bind_model(py::module_& m) {
  py::class_<ConeSensor>(m, "ConeSensor",
                         "Mount (body frame, m, rad) and detection cone of an IR sensor.")
      .def(py::init([](const VectorRef& position, double yaw_rad, double pitch_rad,
                       double half_angle_rad, double min_range_m, double max_range_m, int rings,
                       int azimuths) {
             return ConeSensor{vec3(position, "position"), yaw_rad, pitch_rad, half_angle_rad,
                               min_range_m, max_range_m, rings, azimuths};
           }),
           "position"_a = Vec3(Vec3::Zero()), "yaw_rad"_a = 0.0, "pitch_rad"_a = 0.0,
           "half_angle_rad"_a = ConeSensor().half_angle_rad,
           "min_range_m"_a = ConeSensor().min_range_m, "max_range_m"_a = ConeSensor().max_range_m,
           "rings"_a = ConeSensor().rings, "azimuths"_a = ConeSensor().azimuths,
           "A sensor; validated when a swarm is built.")
      .def_property(
          "position", [](const ConeSensor& s) { return py::make_tuple(
                          s.position_m.x(), s.position_m.y(), s.position_m.z()); },
          [](ConeSensor& s, const VectorRef& p) { s.position_m = vec3(p, "position"); },
          "Mount position (x, y, z) in m, z from the ground (a tuple: assign a whole new one).")
      .def_readwrite("yaw_rad", &ConeSensor::yaw_rad, "Axis heading in the body frame.")
      .def_readwrite("pitch_rad", &ConeSensor::pitch_rad, "Axis tilt, positive down.")
      .def_readwrite("half_angle_rad", &ConeSensor::half_angle_rad, "Cone half angle.")
      .def_readwrite("min_range_m", &ConeSensor::min_range_m, "Closest reading.")
      .def_readwrite("max_range_m", &ConeSensor::max_range_m, "Range; 'nothing' reads this.")
      .def_readwrite("rings", &ConeSensor::rings, "Rings of rays around the axis.")
      .def_readwrite("azimuths", &ConeSensor::azimuths, "Rays per ring (even).");

  py::class_<EpuckModel>(m, "EpuckModel", "e-puck geometry and limits (V-REP defaults).")
      .def(py::init([](double wheel_radius_m, double wheel_separation_m, double body_radius_m,
                       double body_height_m, double max_wheel_speed_rad_s,
                       std::vector<ConeSensor> sensors, double gravity_m_s2) {
             return EpuckModel{wheel_radius_m, wheel_separation_m, body_radius_m,
                               body_height_m, max_wheel_speed_rad_s, std::move(sensors),
                               gravity_m_s2};
           }),
           "wheel_radius_m"_a = EpuckModel().wheel_radius_m,
           "wheel_separation_m"_a = EpuckModel().wheel_separation_m,
           "body_radius_m"_a = EpuckModel().body_radius_m,
           "body_height_m"_a = EpuckModel().body_height_m,
           "max_wheel_speed_rad_s"_a = EpuckModel().max_wheel_speed_rad_s,
           "sensors"_a = default_epuck_sensors(), "gravity_m_s2"_a = EpuckModel().gravity_m_s2,
           "A model; validated when a swarm is built.")
      .def_readwrite("wheel_radius_m", &EpuckModel::wheel_radius_m, "Wheel radius.")
      .def_readwrite("wheel_separation_m", &EpuckModel::wheel_separation_m, "Axle length.")
      .def_readwrite("body_radius_m", &EpuckModel::body_radius_m, "Body cylinder radius.")
      .def_readwrite("body_height_m", &EpuckModel::body_height_m, "Body cylinder height.")
      .def_readwrite("max_wheel_speed_rad_s", &EpuckModel::max_wheel_speed_rad_s,
                     "Wheel speed limit.")
      .def_readwrite("sensors", &EpuckModel::sensors,
                     "IR sensors (a copy: edit items, then assign the whole list back).")
      .def_readwrite("gravity_m_s2", &EpuckModel::gravity_m_s2, "Gravity for the IMU.");
}

void bind_swarm(py::module_& m) {
  py::class_<EpuckSwarm> swarm(m, "EpuckSwarm",
                               "N e-pucks stepped together; adds their bodies to the world, "
                               "which it keeps alive.");
  bindings::bind_noise_setters(swarm, "IR noise per robot and sensor, each (N, K).");
  swarm
      .def(py::init<CollisionWorld&, const EpuckModel&, std::uint64_t>(), "world"_a, "model"_a,
           "seed"_a, py::keep_alive<1, 2>(), "ValueError for an invalid model.")
      .def("add_robot", &EpuckSwarm::add_robot, "handle"_a, "x"_a, "y"_a, "yaw"_a,
           "Adds a robot (body cylinder under handle, group ROBOT); returns its index.")
      .def("remove_robot", &EpuckSwarm::remove_robot, "index"_a,
           "Removes a robot and its body; later robots move up one row, keeping their state "
           "and noise streams. IndexError for a bad index.")
      .def_property_readonly("size", &EpuckSwarm::size, "Number of robots.")
      .def_property_readonly("sensor_count", &EpuckSwarm::sensor_count, "IR sensors per robot.")
      .def("reseed", &EpuckSwarm::reseed, "seed"_a, "Restarts every noise stream from seed.")
      .def("step", &EpuckSwarm::step, "dt_s"_a, "wheel_cmd"_a,
           py::call_guard<py::gil_scoped_release>(),
           "Advances all robots by dt_s with wheel commands (N, 2) = (left, right) rad/s.")
      .def("set_pose", &EpuckSwarm::set_pose, "index"_a, "x"_a, "y"_a, "yaw"_a,
           "Teleports a robot and clears its velocity history.")
      .def("set_odometry", &EpuckSwarm::set_odometry, "index"_a, "x"_a, "y"_a, "yaw"_a,
           "Overwrites a robot's odometry pose.")
      .def(
          "sensor_model",
          [](const EpuckSwarm& s, int i) {
            if (i < 0 || i >= s.sensor_count()) throw py::index_error("sensor index");
            return s.model().sensors[static_cast<size_t>(i)];
          },
          "i"_a, "The model's ConeSensor i (a copy).")
      .def_property_readonly("poses", &EpuckSwarm::poses, "(N, 3) x, y, yaw ground truth.")
      .def_property_readonly("velocities", &EpuckSwarm::velocities,
                             "(N, 3) vx, vy (world), yaw rate.")
      .def_property_readonly("wheel_speeds", &EpuckSwarm::wheel_speeds,
                             "(N, 2) applied wheel speeds, rad/s.")
      .def_property_readonly("wheel_angles", &EpuckSwarm::wheel_angles,
                             "(N, 2) cumulative wheel angles, rad.")
      .def_property_readonly("odometry", &EpuckSwarm::odometry, "(N, 5) x, y, yaw, v, w.")
      .def_property_readonly("ranges_clean", &EpuckSwarm::ranges_clean,
                             "(N, K) clean IR readings, m (max_range_m for nothing).")
      .def_property_readonly("ranges", &EpuckSwarm::ranges, "(N, K) noisy IR readings, m.")
      .def_property_readonly("detected_handles", &EpuckSwarm::detected_handles,
                             "(N, K) int32 handle detected, -1 for none.")
      .def_property_readonly(
          "detected_points",
          [](const EpuckSwarm& s) { return per_sensor_3d(s.detected_points(), s); },
          "(N, K, 3) detected points, sensor frame (zeros for none).")
      .def_property_readonly(
          "detected_normals",
          [](const EpuckSwarm& s) { return per_sensor_3d(s.detected_normals(), s); },
          "(N, K, 3) surface normals at the detected points, sensor frame.")
      .def_property_readonly("accel", &EpuckSwarm::accel, "(N, 3) specific force, m/s^2.")
      .def_property_readonly("gyro", &EpuckSwarm::gyro, "(N, 3) angular velocity, rad/s.")
      .def("reset", &EpuckSwarm::reset, "seed"_a,
           "Starts over where the robots stand: frame 0, noise streams from seed, odometry at "
           "the pose, velocities, wheels and readings as when the robots were added.")
      .def_property_readonly("in_contact", &EpuckSwarm::in_contact,
                             "(N,) bool: the robot touched an obstacle or another robot during "
                             "the last step.")
      .def_property_readonly("frame", &EpuckSwarm::frame, "Steps taken.")
      .def_property_readonly("handles", &EpuckSwarm::handles, "(N,) int32 body handles.")
      .def_property_readonly("stream_ids", &EpuckSwarm::stream_ids,
                             "Noise stream id of each robot (robots added before it).");
}

}  // namespace
void bind_distance(py::module_& m);  // distance_bindings.cpp
void bind_cell(py::module_& m);  // cell_bindings.cpp
void bind_wire(py::module_& m);  // wire_bindings.cpp
void bind_epuck2(py::module_& m);  // epuck2_bindings.cpp
void bind_batched(py::module_& m);  // batched_bindings.cpp
}  // namespace evc

PYBIND11_MODULE(_core, m) {
  m.doc() = "C++ core of epuck_vrep_compat: collision world, e-puck swarm, noise, camera.";
  // An unknown handle is a missing key; everything else maps by pybind11's defaults
  // (invalid_argument -> ValueError, out_of_range -> IndexError).
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const evc::UnknownHandle& unknown) {
      PyErr_SetString(PyExc_KeyError, unknown.what());
    }
  });
  m.attr("GROUP_STATIC") = int(evc::kGroupStatic);
  m.attr("GROUP_ROBOT") = int(evc::kGroupRobot);
  m.attr("GROUP_FLOOR") = int(evc::kGroupFloor);
  m.attr("GROUP_DYNAMIC") = int(evc::kGroupDynamic);
  m.attr("GROUP_ALL") = int(evc::kGroupAll);
  m.attr("WORLD_LIMIT_M") = evc::kWorldLimit_m;
  evc::bind_noise(m);
  evc::bind_world(m);
  evc::bind_model(m);
  evc::bind_swarm(m);
  evc::bind_distance(m);
  evc::bind_cell(m);
  evc::bind_wire(m);
  evc::bind_epuck2(m);
  evc::bind_batched(m);
}
