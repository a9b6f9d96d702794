#include "epuck_vrep_compat/epuck/range_noise.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace evc {

void validate_range_noise(const RangeNoise& noise, double min_range_m, double max_range_m) {
  if (!std::isfinite(noise.probability) || noise.probability < 0.0 || noise.probability > 1.0) {
    throw std::invalid_argument("probability must be in [0, 1], got " +
                                std::to_string(noise.probability));
  }
  if (!std::isfinite(noise.mean_m)) throw std::invalid_argument("mean_m must be finite");
  if (!std::isfinite(noise.stddev_m) || noise.stddev_m < 0.0) {
    throw std::invalid_argument("stddev_m must be finite and >= 0, got " +
                                std::to_string(noise.stddev_m));
  }
  if (!std::isfinite(min_range_m) || !std::isfinite(max_range_m) || min_range_m < 0.0 ||
      max_range_m < min_range_m) {
    throw std::invalid_argument("need 0 <= min_range_m <= max_range_m, both finite");
  }
}

NoisyRanges apply_range_noise(const Eigen::Ref<const VectorXd>& clean_m, double min_range_m,
                              double max_range_m, const RangeNoise& noise, std::uint64_t seed) {
  validate_range_noise(noise, min_range_m, max_range_m);
  if (!clean_m.allFinite()) throw std::invalid_argument("clean must hold only finite values");
  Rng rng(seed);
  NoisyRanges out{VectorXd(clean_m.size()), VectorXb(clean_m.size())};
  for (Eigen::Index i = 0; i < clean_m.size(); ++i) {
    bool applied = false;
    out.ranges_m[i] = apply_range_noise(clean_m[i], min_range_m, max_range_m, noise, rng, applied);
    out.applied[i] = applied;
  }
  return out;
}

}  // namespace evc
