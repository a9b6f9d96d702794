/// @file
/// The e-puck2's time-of-flight distance sensor (ST VL53L0X), one per robot, as the e-puck2
/// driver publishes it on `dist_sens` (sensor_msgs/Range, 0.005–2.0 m, field of view 0.43 rad).
///
/// Frames: the sensor sits in the robot's body frame (x forward, z up, origin on the floor
/// under the wheel axle) at `mount_m`, pitched by `pitch_rad` about the body's y axis (REP 103:
/// a negative pitch looks up; the driver's TF `base_dist_sens` is (0.035, 0, 0.034) with pitch
/// −0.21 rad). It measures along its axis, the sensor's +x.
///
/// Equation: with d the distance along the axis to the first surface (every object but the
/// robot's own body) and, when noise is on, n ~ N(0, (stddev_m + stddev_rel · d)²) from the
/// robot's own stream,
///
///     range = clamp(d + n, min_range_m, max_range_m)   if d <= max_range_m
///           = max_range_m                              if nothing within max_range_m
///
/// as the driver, which clamps the firmware's millimetres to 2000 and then to [min, max]. One
/// normal is drawn per robot per read whether or not something is seen. Each robot's stream is
/// keyed by a stable robot id (not its row), derived from (seed, id, stream kTofStream), so
/// robots added or removed never change another robot's noise.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Stream id of the time-of-flight noise in derive_seed (apart from the swarm's streams).
constexpr std::uint64_t kTofStream = 0x746f66;  // "tof"

/// Mounting, range and noise of the sensor.
struct TofSpec {
  Vec3 mount_m = Vec3(0.035, 0.0, 0.034);  ///< body frame, metres
  double pitch_rad = -0.21;                ///< about body y; negative looks up (REP 103)
  double min_range_m = 0.005;
  double max_range_m = 2.0;
  double stddev_m = 0.003;                 ///< noise SD at distance 0
  double stddev_rel = 0.02;                ///< noise SD per metre of distance
};

/// One time-of-flight sensor on each of N robots.
class TofSensorArray {
 public:
  /// Throws std::invalid_argument unless 0 <= min <= max <= kWorldLimit_m, the mount and pitch
  /// are finite and both SDs are finite and >= 0.
  explicit TofSensorArray(const TofSpec& spec, std::uint64_t seed = 0);

  /// Reads every robot's sensor. @p planar_poses (N, 3): x, y, yaw of each body frame;
  /// @p body_handles (N): each robot's own body (not seen); @p robot_ids (N): stable ids keying
  /// the noise streams; @p noise: draw noise or not. Throws std::invalid_argument for
  /// mismatched sizes or non-finite poses.
  VectorXd read(const CollisionWorld& world, const Eigen::Ref<const RowMatrixXd>& planar_poses,
                const std::vector<int>& body_handles, const std::vector<std::uint64_t>& robot_ids,
                bool noise);

  /// Restarts every stream from @p seed (a reset).
  void reseed(std::uint64_t seed);

  const TofSpec& spec() const { return spec_; }

 private:
  Rng& stream(std::uint64_t robot_id);

  TofSpec spec_;
  std::uint64_t seed_;
  std::unordered_map<std::uint64_t, Rng> streams_;
};

}  // namespace evc
