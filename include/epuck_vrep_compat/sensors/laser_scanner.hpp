/// @file
/// A planar laser scanner such as the Hokuyo URG-04LX-UG01 (models.md §5: 682 beams over
/// ±119.7°, 0.02–5.6 m, σ = 0.01 m below 1 m and 0.01 r beyond).
///
/// Frames: the scanner frame is REP 103; beam k leaves its origin in the local x-y plane at
/// θ_k = angle_min_rad + k angle_increment_rad, measured from +x towards +y (the ROS LaserScan
/// convention), along (cos θ_k, sin θ_k, 0).
///
/// Equation: with d_k the distance to the first surface along beam k (objects in the group
/// mask, the ignore handle skipped) and n_k ~ N(0, 1),
///
///     σ(d) = max(sigma_min_m, sigma_rel d)
///     r_k  = clamp(d_k + σ(d_k) n_k, range_min_m, range_max_m)   if range_min_m <= d_k
///          = -inf                                               if d_k < range_min_m
///          = +inf                                               if no hit within range_max_m
///
/// (±inf follow REP 117.) Noise never turns a valid reading into an invalid one. One Rng owned
/// by the scanner gives n_0 … n_{count-1} in beam order on every scan with noise on, whether or
/// not the beams hit, so the same seed and scene give the same scans, bit for bit.
///
/// Cost: the beams share an origin and a plane, so one broadphase query keeps the objects
/// whose bounding spheres cross the scan plane within range, and each beam tests only those
/// (the hits equal one CollisionWorld::ray_cast per beam; test_cell_sensors.py checks it).
#pragma once

#include <cstdint>
#include <vector>

#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Beam layout, limits and noise of a scanner.
struct LaserSpec {
  /// First beam: Hokuyo step 44, 340 steps of 2π/1024 right of the front step 384 (-119.53°).
  double angle_min_rad = -340.0 * 6.283185307179586 / 1024.0;
  double angle_increment_rad = 6.283185307179586 / 1024.0;  ///< Hokuyo ARES: 1024 steps/turn
  int count = 682;                          ///< beams
  double range_min_m = 0.02;
  double range_max_m = 5.6;
  double sigma_min_m = 0.0;                 ///< noise SD floor, metres (0 with sigma_rel 0: off)
  double sigma_rel = 0.0;                   ///< noise SD per metre of range
};

/// A scanner with its own noise stream.
class LaserScanner {
 public:
  /// Throws std::invalid_argument unless the angles are finite, count >= 1, 0 <= range_min_m
  /// < range_max_m <= kWorldLimit_m and both noise parameters are finite and >= 0.
  explicit LaserScanner(const LaserSpec& spec, std::uint64_t seed = 0);

  /// One scan from @p pose (scanner frame in the world): count ranges, metres, float32 as in
  /// sensor_msgs/LaserScan. Throws std::invalid_argument for a bad pose.
  std::vector<float> scan(const CollisionWorld& world, const Pose& pose, int ignore_handle = -1,
                          int mask = kGroupAll);

  /// Restarts the noise stream from @p seed.
  void reseed(std::uint64_t seed) { rng_ = Rng(seed); }

  const LaserSpec& spec() const { return spec_; }

 private:
  LaserSpec spec_;
  std::vector<Vec3> beams_;  // unit directions, scanner frame
  Rng rng_;
};

}  // namespace evc
