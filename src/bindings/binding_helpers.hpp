// Argument conversions shared by the binding translation units (core_module.cpp,
// cell_bindings.cpp): poses from numpy vectors, named ValueErrors, numpy copies of results.
#pragma once

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>

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

}  // namespace bindings
}  // namespace evc
