#include "epuck_vrep_compat/sensors/depth_buffer.hpp"

#include <cmath>
#include <stdexcept>

namespace evc {

void vrep_depth_buffer(const float* depth_m, float* out, std::size_t height, std::size_t width,
                       double near_m, double far_m) {
  if (!(std::isfinite(near_m) && std::isfinite(far_m) && near_m < far_m)) {
    throw std::invalid_argument("need near_m < far_m, both finite");
  }
  const double range_m = far_m - near_m;
  for (std::size_t r = 0; r < height; ++r) {
    const float* row = depth_m + (height - 1 - r) * width;
    float* row_out = out + r * width;
    for (std::size_t c = 0; c < width; ++c) {
      double value = (static_cast<double>(row[c]) - near_m) / range_m;
      // np.clip's order: a NaN compares false both ways and stays NaN
      value = value < 0.0 ? 0.0 : (value > 1.0 ? 1.0 : value);
      row_out[c] = static_cast<float>(value);
    }
  }
}

}  // namespace evc
