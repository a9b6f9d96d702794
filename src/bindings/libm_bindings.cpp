// epuck_vrep_compat._libm: the C library's tanh, exp, log, cos, sin and atan2 applied element
// by element to float64 arrays (geometry/fixed_order.py's libm without a Python call per
// element). A module of its own, not part of _core: the pure layers (geometry, policy) and the
// clients that use them (policy_node) must not load the simulator's core. The same functions Python's math module calls, so the same bits: scalar calls
// (no fast-math, so the compiler does not swap in libmvec's vector variants), whatever the
// array's layout or alignment (the input is copied to a C-ordered, aligned float64 array).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace py = pybind11;
using namespace py::literals;

namespace evc {
namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

Doubles same_shape(const Doubles& like) {
  return Doubles(std::vector<py::ssize_t>(like.shape(), like.shape() + like.ndim()));
}

template <double (*F)(double)>
Doubles unary(const Doubles& x) {
  Doubles out = same_shape(x);
  const double* in = x.data();
  double* o = out.mutable_data();
  const py::ssize_t n = x.size();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) o[i] = F(in[i]);
  }
  return out;
}

Doubles atan2_of(const Doubles& y, const Doubles& x) {
  if (y.ndim() != x.ndim() ||
      !std::equal(y.shape(), y.shape() + y.ndim(), x.shape())) {
    throw std::invalid_argument("atan2: y and x must have the same shape (broadcast them first)");
  }
  Doubles out = same_shape(y);
  const double* a = y.data();
  const double* b = x.data();
  double* o = out.mutable_data();
  const py::ssize_t n = y.size();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) o[i] = std::atan2(a[i], b[i]);
  }
  return out;
}

// Plain function pointers to the C library's double versions (not the overload sets).
double c_tanh(double v) { return std::tanh(v); }
double c_exp(double v) { return std::exp(v); }
double c_log(double v) { return std::log(v); }
double c_cos(double v) { return std::cos(v); }
double c_sin(double v) { return std::sin(v); }

}  // namespace
}  // namespace evc

PYBIND11_MODULE(_libm, libm) {
  using namespace evc;
  libm.doc() = "The C library's functions element by element over float64 arrays (the bits of "
               "Python's math module, whatever the processor's SIMD or the array's layout).";
  libm.def("tanh", &unary<c_tanh>, "x"_a, "tanh of each element.");
  libm.def("exp", &unary<c_exp>, "x"_a, "exp of each element.");
  libm.def("log", &unary<c_log>, "x"_a, "log of each element (-inf at 0, nan below).");
  libm.def("cos", &unary<c_cos>, "x"_a, "cos of each element.");
  libm.def("sin", &unary<c_sin>, "x"_a, "sin of each element.");
  libm.def("atan2", &atan2_of, "y"_a, "x"_a, "atan2(y, x) of each pair (same shapes).");
}
