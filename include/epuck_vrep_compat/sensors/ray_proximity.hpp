/// @file
/// A batch of single-ray proximity sensors, as V-REP's "ray type" proximity sensor (the 11-ray
/// matrix on the IRB 140, models.md §2.3: 0.02–0.08 m).
///
/// Frames: sensor i sits at pose_i; it looks along its local +z axis (V-REP's convention, not
/// REP 103's +x). Its ray runs from the sensor origin up to max_range_m, so an object nearer
/// than min_range_m blinds the sensor rather than being seen through.
///
/// Equation: with d the distance to the first surface along the ray (objects in the group mask,
/// the sensor's ignore handle skipped) and, when noise is on, n ~ N(0, stddev_m²),
///
///     detected = min_range_m <= d <= max_range_m
///     distance = clamp(d + n, min_range_m, max_range_m)   if detected
///              = -inf                                     if d < min_range_m (too close)
///              = +inf                                     if nothing within max_range_m
///     point    = (0, 0, distance)                         sensor frame, zero if not detected
///     normal   = R_i^T n_world                            sensor frame, zero if not detected
///
/// (±inf follow REP 117, so a sensor_msgs/Range can carry them as they are.) Noise is drawn
/// from one Rng owned by the array: one normal per sensor per read, in sensor order, whether
/// or not it detects, so a replay with the same seed and scene gives the same readings.
#pragma once

#include <cstdint>
#include <vector>

#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Readings of M sensors, row i for sensor i.
struct ProximityReadings {
  VectorXi detected;    ///< 1 where min_range_m <= distance <= max_range_m, else 0
  VectorXd distance_m;  ///< as in the file comment: the reading, or ±inf
  VectorXi handle;      ///< object detected, -1 for none
  RowMatrixXd point;    ///< (M, 3) detected point, sensor frame, zero for none
  RowMatrixXd normal;   ///< (M, 3) surface normal at the point, sensor frame, zero for none
};

/// M ray proximity sensors sharing one noise stream.
class RayProximityArray {
 public:
  /// Ranges per sensor (metres). Throws std::invalid_argument unless both have the same length
  /// and 0 <= min_range_m <= max_range_m <= kWorldLimit_m, and stddev_m is finite and >= 0.
  RayProximityArray(const VectorXd& min_range_m, const VectorXd& max_range_m,
                    double noise_stddev_m = 0.0, std::uint64_t seed = 0);

  /// Reads every sensor at its pose (sensor frame in the world). @p ignore_handles holds one
  /// handle per sensor (its carrier, or -1). Throws std::invalid_argument for a wrong count.
  ProximityReadings read(const CollisionWorld& world, const std::vector<Pose>& poses,
                         const std::vector<int>& ignore_handles, int mask = kGroupAll);

  /// Restarts the noise stream from @p seed.
  void reseed(std::uint64_t seed) { rng_ = Rng(seed); }

  int size() const { return static_cast<int>(min_range_m_.size()); }
  const VectorXd& min_range_m() const { return min_range_m_; }
  const VectorXd& max_range_m() const { return max_range_m_; }
  double noise_stddev_m() const { return noise_stddev_m_; }

 private:
  VectorXd min_range_m_;
  VectorXd max_range_m_;
  double noise_stddev_m_;
  Rng rng_;
};

}  // namespace evc
