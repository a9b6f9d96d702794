#include "epuck_vrep_compat/sensors/depth_noise.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "random/ziggurat.hpp"

namespace evc {
namespace {

void check_non_negative(double value, const char* name) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw std::invalid_argument(std::string(name) + " must be finite and >= 0");
  }
}

}  // namespace

DepthNoise::DepthNoise(const DepthNoiseSpec& spec, std::uint64_t seed) : spec_(spec), rng_(seed) {
  check_non_negative(spec.a_m, "a_m");
  check_non_negative(spec.b_per_m, "b_per_m");
  check_non_negative(spec.inverse_depth_step_per_m, "inverse_depth_step_per_m");
  if (!std::isfinite(spec.c_m)) throw std::invalid_argument("c_m must be finite");
}

double DepthNoise::sigma_m(double depth_m) const {
  const double offset = depth_m - spec_.c_m;
  return spec_.a_m + spec_.b_per_m * offset * offset;
}

void DepthNoise::apply(const float* depth_m, float* out_m, std::size_t count, double near_m,
                       double far_m) {
  if (!(std::isfinite(near_m) && std::isfinite(far_m) && near_m >= 0.0 && near_m < far_m)) {
    throw std::invalid_argument("need 0 <= near_m < far_m, both finite");
  }
  if (std::any_of(depth_m, depth_m + count, [](float z) { return !(z >= 0.0f); })) {
    throw std::invalid_argument("depth must hold values >= 0 (+inf allowed), no NaN");
  }
  const double step = spec_.inverse_depth_step_per_m;
  const ZigguratTables& tables = ziggurat_tables();
  const auto far = static_cast<float>(far_m);
  for (std::size_t i = 0; i < count; ++i) {
    const double z = depth_m[i];
    const double n = ziggurat_normal_inline(rng_, tables);    // drawn for every pixel
    if (z >= far_m) {               // no return: far_m whatever was drawn
      out_m[i] = far;
      continue;
    }
    double noisy = z + sigma_m(z) * n;
    if (step > 0.0 && noisy > 0.0) noisy = 1.0 / (step * std::round(1.0 / (step * noisy)));
    out_m[i] = static_cast<float>(std::clamp(noisy, near_m, far_m));
  }
}

}  // namespace evc
