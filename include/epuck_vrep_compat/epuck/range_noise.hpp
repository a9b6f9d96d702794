/// @file
/// The proximity-sensor noise model of V-REP's e-puck script, applied to one reading at a time.
///
/// For a clean reading r in [r_min, r_max] (metres) and one generator:
///
///     u ~ U(0, 1]
///     if u <= p:                       (the reading is noisy with probability p)
///         n = |mean_m + stddev_m * N(0, 1)|     (the size of the error, always >= 0)
///         r' = r + n            if r == r_min
///         r' = r - n            if r == r_max        (nothing detected: noise can only shorten)
///         r' = r + n or r - n   otherwise, each with probability 1/2 (one more draw: <= 0.5 adds)
///     else:
///         r' = r
///     r' = clamp(r', r_min, r_max)
///
/// The error's size is folded to be non-negative because the e-puck paper configured mean_m and
/// stddev_m as those of the real sensor's errors, which are one-sided (0.05 m minus the reading
/// in open space): a signed draw would turn into a longer reading at r_max, be clamped away, and
/// hide part of the configured probability. With mean_m >= 3 stddev_m the folding changes the
/// distribution by less than 0.2 %.
///
/// The draw order above is part of the model: a replay with the same seed gives the same values.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

/// Parameters of the noise model of one sensor.
struct RangeNoise {
  double probability = 0.0;  ///< chance that a reading is noisy, in [0, 1]
  double mean_m = 0.0;       ///< mean of the error's size before folding, metres
  double stddev_m = 0.0;     ///< its standard deviation before folding, metres (>= 0)
};

/// Throws std::invalid_argument unless the parameters are finite, 0 <= probability <= 1 and
/// stddev_m >= 0, and unless 0 <= min_range_m <= max_range_m.
void validate_range_noise(const RangeNoise& noise, double min_range_m, double max_range_m);

/// Applies the model to one clean reading with @p rng; sets @p applied when noise was added.
/// Parameters are assumed valid (see validate_range_noise); this runs per sensor per step, so it
/// is defined here to be inlined (one draw when no noise is added).
inline double apply_range_noise(double clean_m, double min_range_m, double max_range_m,
                                const RangeNoise& noise, Rng& rng, bool& applied) {
  double reading = clean_m;
  applied = rng.uniform() <= noise.probability;
  if (applied) {
    const double magnitude = std::abs(noise.mean_m + noise.stddev_m * rng.normal());
    if (clean_m == min_range_m) {
      reading += magnitude;
    } else if (clean_m == max_range_m) {
      reading -= magnitude;
    } else {
      reading += rng.uniform() <= 0.5 ? magnitude : -magnitude;
    }
  }
  return std::clamp(reading, min_range_m, max_range_m);
}

/// Noisy readings and which of them received noise.
struct NoisyRanges {
  VectorXd ranges_m;  ///< noisy readings, metres, in [min, max]
  VectorXb applied;   ///< true where the reading was made noisy
};

/// Applies the model to every reading in order with one Rng(seed); validates the parameters
/// and rejects non-finite readings (std::invalid_argument).
NoisyRanges apply_range_noise(const Eigen::Ref<const VectorXd>& clean_m, double min_range_m,
                              double max_range_m, const RangeNoise& noise, std::uint64_t seed);

}  // namespace evc
