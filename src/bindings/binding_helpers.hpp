// Argument conversions and bindings shared by the binding translation units (core_module.cpp,
// cell_bindings.cpp): poses from numpy vectors, named ValueErrors, numpy copies of results.
#pragma once

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "epuck_vrep_compat/world/types.hpp"

namespace evc {
namespace bindings {

using VectorRef = Eigen::Ref<const VectorXd>;
using MatrixRef = Eigen::Ref<const RowMatrixXd>;

inline VectorXd finite_vector(const VectorRef& values, Eigen::Index size, const char* name) {
  if (values.size() != size || !values.allFinite()) {
    throw std::invalid_argument(std::string(name) + " must hold " + std::to_string(size) +
                                " finite values");
  }
  return values;
}

inline Vec3 vec3(const VectorRef& values, const char* name) {
  return finite_vector(values, 3, name);
}

// A unit quaternion from (x, y, z, w); zero or non-finite values are a named ValueError.
inline Quat quat_xyzw(const VectorRef& values, const char* name) {
  const VectorXd q = finite_vector(values, 4, name);
  if (q.norm() < 1e-9) throw std::invalid_argument(std::string(name) + " must be non-zero");
  return Quat(q[3], q[0], q[1], q[2]).normalized();
}

inline Pose pose_of(const VectorRef& position, const VectorRef& quaternion) {
  return Pose{vec3(position, "position"), quat_xyzw(quaternion, "quaternion")};
}

// A numpy array of the given shape holding a copy of the data.
template <typename T>
pybind11::array_t<T> array_copy(const std::vector<T>& data,
                                std::vector<pybind11::ssize_t> shape) {
  pybind11::array_t<T> out(shape);
  std::memcpy(out.mutable_data(), data.data(), data.size() * sizeof(T));
  return out;
}

// The noise setters EpuckSwarm and BatchedWorlds share (one API, so that Python's
// NoiseSettings.apply sets either): IR, IMU noise and bias, wheel slip, N rows each.
// ``out`` as the float32 (height, width) image a function writes to in place (no copy):
// std::invalid_argument unless it is a writable, C-contiguous float32 array of that shape.
inline pybind11::array_t<float> float_image_out(const pybind11::object& out,
                                                pybind11::ssize_t height,
                                                pybind11::ssize_t width) {
  namespace py = pybind11;
  if (py::isinstance<py::array_t<float>>(out)) {
    auto array = py::reinterpret_borrow<py::array_t<float>>(out);
    if ((array.flags() & py::array::c_style) && array.writeable() && array.ndim() == 2 &&
        array.shape(0) == height && array.shape(1) == width) {
      return array;
    }
  }
  throw std::invalid_argument("out must be a writable C-contiguous float32 array of shape (" +
                              std::to_string(height) + ", " + std::to_string(width) + ")");
}

template <typename T>
void bind_noise_setters(pybind11::class_<T>& cls, const char* ir_doc) {
  using namespace pybind11::literals;
  cls.def("set_ir_noise", &T::set_ir_noise, "probability"_a, "mean_m"_a, "stddev_m"_a, ir_doc)
      .def("set_imu_noise", &T::set_imu_noise, "accel_stddev"_a, "gyro_stddev"_a,
           "IMU noise SD per robot and axis, each (N, 3): m/s^2 and rad/s.")
      .def("set_imu_bias", &T::set_imu_bias, "accel_bias"_a, "gyro_bias"_a,
           "Constant IMU bias per robot and axis, each (N, 3): m/s^2 and rad/s.")
      .def("set_slip_noise", &T::set_slip_noise, "stddev"_a,
           "Relative wheel-speed noise SD per robot, (N,).");
}

}  // namespace bindings
}  // namespace evc
