// The industrial cell's sensors in epuck_vrep_compat._core: batched moves of a CollisionWorld,
// ray proximity sensors, a laser scanner, Kinect depth noise and V-REP's blob detection. A
// thin shim like core_module.cpp: it converts and names arguments, releases the GIL around the
// work, and leaves all behaviour to the core.
#include <cstring>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "binding_helpers.hpp"
#include "epuck_vrep_compat/sensors/blob_detection.hpp"
#include "epuck_vrep_compat/sensors/depth_buffer.hpp"
#include "epuck_vrep_compat/sensors/depth_noise.hpp"
#include "epuck_vrep_compat/sensors/laser_scanner.hpp"
#include "epuck_vrep_compat/sensors/ray_proximity.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace evc {
namespace {

using bindings::array_copy;
using bindings::float_image_out;
using bindings::MatrixRef;
using bindings::pose_of;
using bindings::VectorRef;

std::invalid_argument bad(const char* name, const std::string& requirement) {
  return std::invalid_argument(std::string(name) + " must " + requirement);
}

// Poses from positions (M, 3) and quaternions (M, 4) x, y, z, w; the core checks the values.
std::vector<Pose> poses_of(const MatrixRef& positions, const MatrixRef& quaternions) {
  if (positions.cols() != 3) throw bad("positions", "have shape (M, 3)");
  if (quaternions.cols() != 4 || quaternions.rows() != positions.rows()) {
    throw bad("quaternions", "have shape (M, 4) (x, y, z, w), M = len(positions)");
  }
  std::vector<Pose> poses(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const auto q = quaternions.row(i);
    poses[static_cast<std::size_t>(i)] =
        Pose{positions.row(i).transpose(), Quat(q[3], q[0], q[1], q[2])};
  }
  return poses;
}

// count handles from an (count,) integer array, or from one int repeated if @p scalar_ok.
std::vector<int> handles_of(const py::object& value, std::size_t count, const char* name,
                            bool scalar_ok) {
  const py::array array = py::array::ensure(value);
  const char kind = array ? array.dtype().kind() : '?';
  if (kind != 'i' && kind != 'u') throw bad(name, "hold integers");
  const auto ints = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(array);
  if (scalar_ok && ints.ndim() == 0) return std::vector<int>(count, *ints.data());
  if (ints.ndim() != 1 || static_cast<std::size_t>(ints.shape(0)) != count) {
    throw bad(name, std::string(scalar_ok ? "be an int or " : "") + "have shape (" +
                        std::to_string(count) + ",)");
  }
  return std::vector<int>(ints.data(), ints.data() + count);
}

void bind_set_poses(py::module_& m) {
  auto world = py::reinterpret_borrow<py::class_<CollisionWorld>>(m.attr("CollisionWorld"));
  world.def(
      "set_poses",
      [](CollisionWorld& w, const py::object& handles, const MatrixRef& positions,
         const MatrixRef& quaternions) {
        std::vector<Pose> poses = poses_of(positions, quaternions);
        w.set_poses(handles_of(handles, poses.size(), "handles", false), poses);
      },
      "handles"_a, "positions"_a, "quaternions"_a,
      "Moves M objects at once: handles (M,) int, positions (M, 3), quaternions (M, 4) x, y, "
      "z, w. All or none: KeyError for an unknown handle, ValueError for bad shapes or values "
      "(naming the argument or the pose index), and nothing moves.");
}

void bind_proximity(py::module_& m) {
  py::class_<RayProximityArray>(
      m, "RayProximityArray",
      "M single-ray proximity sensors (V-REP ray type): each looks along its local +z axis "
      "from its origin and detects the first surface at min_range_m <= d <= max_range_m.")
      .def(py::init<const VectorXd&, const VectorXd&, double, std::uint64_t>(),
           "min_range_m"_a, "max_range_m"_a, "noise_stddev_m"_a = 0.0, "seed"_a = 0,
           "Ranges (M,) each, m; Gaussian range noise of SD noise_stddev_m (0: none) from "
           "its own Rng(seed). ValueError unless 0 <= min <= max <= 1e6 and stddev >= 0.")
      .def(
          "read",
          [](RayProximityArray& a, const CollisionWorld& world, const MatrixRef& positions,
             const MatrixRef& quaternions, const py::object& ignore_handles, int mask) {
            const std::vector<Pose> poses = poses_of(positions, quaternions);
            const std::vector<int> ignore =
                handles_of(ignore_handles, poses.size(), "ignore_handles", true);
            ProximityReadings r;
            {
              py::gil_scoped_release release;
              r = a.read(world, poses, ignore, mask);
            }
            return py::make_tuple(std::move(r.detected), std::move(r.distance_m),
                                  std::move(r.point), std::move(r.handle),
                                  std::move(r.normal));
          },
          "world"_a, "positions"_a, "quaternions"_a, "ignore_handles"_a = -1,
          "mask"_a = int(kGroupAll),
          "Reads the sensors at poses (M, 3) and (M, 4) x, y, z, w (sensor frames in the "
          "world); ignore_handles (M,) or one int. Returns V-REP's order: (detected (M,) int32 "
          "0/1, distance (M,) m (+inf: nothing within max, -inf: first hit nearer than min), "
          "point (M, 3) sensor frame, handle (M,) int32 -1 for none, normal (M, 3) sensor "
          "frame); zeros where not detected.")
      .def("reseed", &RayProximityArray::reseed, "seed"_a, "Restarts the noise stream.")
      .def_property_readonly("size", &RayProximityArray::size, "Number of sensors M.")
      .def_property_readonly("min_range_m", &RayProximityArray::min_range_m, "(M,) m.")
      .def_property_readonly("max_range_m", &RayProximityArray::max_range_m, "(M,) m.")
      .def_property_readonly("noise_stddev_m", &RayProximityArray::noise_stddev_m, "m.");
}

void bind_laser(py::module_& m) {
  const LaserSpec hokuyo;
  py::class_<LaserScanner>(
      m, "LaserScanner",
      "Planar laser scanner (defaults: Hokuyo URG-04LX-UG01). Beam k lies in the local x-y "
      "plane at angle_min_rad + k angle_increment_rad from +x towards +y; noise SD "
      "max(sigma_min_m, sigma_rel r) from its own Rng(seed).")
      .def(py::init([](double angle_min_rad, double angle_increment_rad, int count,
                       double range_min_m, double range_max_m, double sigma_min_m,
                       double sigma_rel, std::uint64_t seed) {
             return LaserScanner(LaserSpec{angle_min_rad, angle_increment_rad, count,
                                           range_min_m, range_max_m, sigma_min_m, sigma_rel},
                                 seed);
           }),
           "angle_min_rad"_a = hokuyo.angle_min_rad,
           "angle_increment_rad"_a = hokuyo.angle_increment_rad, "count"_a = hokuyo.count,
           "range_min_m"_a = hokuyo.range_min_m, "range_max_m"_a = hokuyo.range_max_m,
           "sigma_min_m"_a = 0.0, "sigma_rel"_a = 0.0, "seed"_a = 0,
           "ValueError for non-finite angles, count < 1, not 0 <= range_min_m < range_max_m, "
           "or negative noise parameters (models.md: sigma_min_m = 0.01, sigma_rel = 0.01).")
      .def(
          "scan",
          [](LaserScanner& s, const CollisionWorld& world, const VectorRef& position,
             const VectorRef& quaternion, int ignore_handle, int mask) {
            const Pose pose = pose_of(position, quaternion);
            std::vector<float> ranges;
            {
              py::gil_scoped_release release;
              ranges = s.scan(world, pose, ignore_handle, mask);
            }
            return array_copy(ranges, {static_cast<py::ssize_t>(ranges.size())});
          },
          "world"_a, "position"_a, "quaternion"_a, "ignore_handle"_a = -1,
          "mask"_a = int(kGroupAll),
          "One scan from the scanner frame at position (3,), quaternion (4,) x, y, z, w. "
          "Returns ranges float32 (count,) m, REP 117: +inf for no return within range_max_m, "
          "-inf for a return nearer than range_min_m.")
      .def("reseed", &LaserScanner::reseed, "seed"_a, "Restarts the noise stream.")
      .def_property_readonly("angle_min_rad", [](const LaserScanner& s) {
        return s.spec().angle_min_rad; }, "First beam angle.")
      .def_property_readonly("angle_increment_rad", [](const LaserScanner& s) {
        return s.spec().angle_increment_rad; }, "Angle between beams.")
      .def_property_readonly("count", [](const LaserScanner& s) { return s.spec().count; },
                             "Beams per scan.")
      .def_property_readonly("range_min_m", [](const LaserScanner& s) {
        return s.spec().range_min_m; }, "Nearest valid range.")
      .def_property_readonly("range_max_m", [](const LaserScanner& s) {
        return s.spec().range_max_m; }, "Farthest valid range.")
      .def_property_readonly("sigma_min_m", [](const LaserScanner& s) {
        return s.spec().sigma_min_m; }, "Noise SD floor, m.")
      .def_property_readonly("sigma_rel", [](const LaserScanner& s) {
        return s.spec().sigma_rel; }, "Noise SD per metre of range.");
}

void bind_depth_noise(py::module_& m) {
  const DepthNoiseSpec kinect;
  py::class_<DepthNoise>(
      m, "DepthNoise",
      "Kinect v1 axial depth noise, sigma_z = a_m + b_per_m (z - c_m)^2, optional inverse "
      "depth quantisation (step k per metre, 0: off), from its own Rng(seed).")
      .def(py::init([](double a_m, double b_per_m, double c_m, double inverse_depth_step_per_m,
                       std::uint64_t seed) {
             return DepthNoise(DepthNoiseSpec{a_m, b_per_m, c_m, inverse_depth_step_per_m},
                               seed);
           }),
           "a_m"_a = kinect.a_m, "b_per_m"_a = kinect.b_per_m, "c_m"_a = kinect.c_m,
           "inverse_depth_step_per_m"_a = 0.0, "seed"_a = 0,
           "ValueError for negative or non-finite a_m, b_per_m, inverse_depth_step_per_m or "
           "a non-finite c_m.")
      .def(
          "apply",
          [](DepthNoise& noise,
             const py::array_t<float, py::array::c_style | py::array::forcecast>& depth,
             double near_m, double far_m, py::object out) {
            if (depth.ndim() != 2) throw bad("depth", "be a 2-D (H, W) array of metres");
            py::array_t<float> noisy_array =
                out.is_none() ? py::array_t<float>({depth.shape(0), depth.shape(1)})
                              : float_image_out(out, depth.shape(0), depth.shape(1));
            const float* in = depth.data();
            float* noisy = noisy_array.mutable_data();
            const auto count = static_cast<std::size_t>(depth.size());
            {
              py::gil_scoped_release release;
              noise.apply(in, noisy, count, near_m, far_m);
            }
            return noisy_array;
          },
          "depth"_a, "near_m"_a, "far_m"_a, "out"_a = py::none(),
          "Noisy copy (float32 (H, W)) of a depth image (m): values >= far_m (no return) "
          "stay far_m, the rest are clamped to [near_m, far_m]. ``out``: a writable float32 "
          "C-contiguous (H, W) array to write it to instead of a new one (``depth`` itself "
          "too), returned. ValueError for NaN or negative depths, or not 0 <= near_m < far_m.")
      .def("sigma_m", &DepthNoise::sigma_m, "depth_m"_a, "sigma_z at a depth, m.")
      .def("reseed", &DepthNoise::reseed, "seed"_a, "Restarts the noise stream.");
}

void bind_depth_buffer(py::module_& m) {
  m.def(
      "vrep_depth_buffer",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& depth,
         double near_m, double far_m) {
        if (depth.ndim() != 2) throw bad("depth", "be a 2-D (H, W) array of metres");
        const auto height = static_cast<std::size_t>(depth.shape(0));
        const auto width = static_cast<std::size_t>(depth.shape(1));
        py::array_t<float> out({depth.shape(0), depth.shape(1)});
        const float* in = depth.data();
        float* buffer = out.mutable_data();
        {
          py::gil_scoped_release release;
          vrep_depth_buffer(in, buffer, height, width, near_m, far_m);
        }
        return out;
      },
      "depth"_a, "near_m"_a, "far_m"_a,
      "V-REP's depth buffer (float32 (H, W), row 0 the image's bottom row) of a depth image "
      "(m, row 0 at the top): (depth - near_m) / (far_m - near_m) in float64, clipped to "
      "[0, 1], then float32, as numpy computes it. ValueError unless near_m < far_m, finite.");
}

void bind_blobs(py::module_& m) {
  m.def(
      "detect_blobs",
      [](const py::array& image, double threshold, double min_size) {
        const char kind = image.dtype().kind();
        const bool rgb = image.ndim() == 3 && image.shape(2) == 3;
        if ((kind != 'u' || image.itemsize() != 1) && kind != 'b') {
          throw bad("image", "be uint8 or bool");
        }
        if (image.ndim() != 2 && !rgb) throw bad("image", "have shape (H, W) or (H, W, 3)");
        const auto pixels =
            py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
        const int height = static_cast<int>(image.shape(0));
        const int width = static_cast<int>(image.shape(1));
        std::vector<float> packet;
        {
          py::gil_scoped_release release;
          packet = blob_packet(
              detect_blobs(pixels.data(), height, width, rgb ? 3 : 1, threshold, min_size));
        }
        return array_copy(packet, {static_cast<py::ssize_t>(packet.size())});
      },
      "image"_a, "threshold"_a = 0.5, "min_size"_a = 0.0,
      "V-REP's blob detection on an image whose row 0 is the TOP. Object pixels: nonzero in "
      "a mask (H, W) uint8/bool; mean intensity / 255 >= threshold in an RGB (H, W, 3) uint8 "
      "image. 8-connected blobs smaller than min_size (fraction of the image) are dropped; "
      "the rest come largest first. Returns V-REP's packet, float32: [count, 6, then per blob "
      "size (fraction of the image), orientation (rad, CCW, modulo pi/2), x, y (box centre, "
      "0..1, x from the left, y from the BOTTOM), width, height (box sides over W and H)].");
}

}  // namespace

void bind_cell(py::module_& m) {
  bind_set_poses(m);
  bind_proximity(m);
  bind_laser(m);
  bind_depth_noise(m);
  bind_depth_buffer(m);
  bind_blobs(m);
}

}  // namespace evc
