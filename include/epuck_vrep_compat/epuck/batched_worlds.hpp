/// @file
/// B independent worlds of R e-pucks each, stepped together: the core of the learning
/// environments, which step many small worlds at once.
///
/// World b is a CollisionWorld of its own (its static obstacles and its robots' bodies) and an
/// EpuckSwarm of its own, seeded with its own seed: a world's arrays are exactly those of a
/// standalone EpuckSwarm on a CollisionWorld holding the same obstacles under the same handles,
/// with the same seed and commands, the sensors and noise behind the simulator's ROS topics.
/// Worlds share nothing, so what happens in one never changes another's numbers.
///
/// Handles: world b's obstacles get 0, 1, 2, ... in the order they are added (again from 0 after
/// clear_obstacles); robot r's body is kRobotHandleBase + r, above every obstacle, as the
/// simulator's robots come after its arena.
///
/// Rows: every per-robot array has N = B * R rows, row b * R + r for robot r of world b. The
/// outputs live in contiguous buffers filled by step(); after set_pose or reset_world the rows
/// of that world are refreshed when next read. Not thread-safe: nothing may touch the object
/// while step() runs (the binding releases the GIL for it).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "epuck_vrep_compat/epuck/epuck_model.hpp"
#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Colour of the obstacles added by BatchedWorlds unless told otherwise (the arena's grey).
inline const Vec3 kObstacleRgb{0.6, 0.6, 0.6};

/// B worlds of R e-pucks; see the file comment.
class BatchedWorlds {
 public:
  /// Body handle of robot 0 in every world; robot r's is kRobotHandleBase + r.
  static constexpr int kRobotHandleBase = 1 << 30;
  /// Most robots in all worlds together.
  static constexpr std::int64_t kMaxRobots = 10'000'000;

  /// @p worlds >= 1 worlds of @p robots >= 1 robots each, world b's swarm seeded with
  /// seeds[b]; std::invalid_argument for bad counts, seeds.size() != worlds or a bad model.
  /// The robots start on a grid of 10 cm cells about the origin, heading 0, with every noise
  /// off; place them with set_pose.
  BatchedWorlds(const EpuckModel& model, int worlds, int robots,
                const std::vector<std::uint64_t>& seeds);
  ~BatchedWorlds();
  BatchedWorlds(const BatchedWorlds&) = delete;
  BatchedWorlds& operator=(const BatchedWorlds&) = delete;

  /// Number of worlds, B.
  int worlds() const { return static_cast<int>(worlds_.size()); }
  /// Robots per world, R.
  int robots() const { return robots_; }
  /// Robots in all, N = B * R.
  int size() const { return worlds() * robots_; }
  /// IR sensors per robot, K.
  int sensor_count() const { return sensor_count_; }

  /// Adds a static box (group STATIC, as the arena's walls and obstacles) centred at
  /// @p center_m, turned by @p yaw_rad about z; returns its handle in that world.
  /// std::out_of_range for a bad world, std::invalid_argument for bad values.
  int add_box(int world, const Vec3& center_m, const Vec3& half_extents_m, double yaw_rad,
              const Vec3& rgb = kObstacleRgb);
  /// Adds a static upright cylinder centred at @p center_m; returns its handle.
  int add_cylinder(int world, const Vec3& center_m, double radius_m, double height_m,
                   const Vec3& rgb = kObstacleRgb);
  /// Removes every obstacle of a world; the next one added gets handle 0 again.
  void clear_obstacles(int world);

  /// Teleports robot @p robot of @p world, its odometry too, and clears its velocity history
  /// (EpuckSwarm::set_pose and set_odometry). std::out_of_range, std::invalid_argument.
  void set_pose(int world, int robot, double x_m, double y_m, double yaw_rad);
  /// Starts a world over (EpuckSwarm::reset): frame 0, its noise streams restarted from
  /// @p seed, velocities and readings cleared. Poses, obstacles and noise settings stay.
  void reset_world(int world, std::uint64_t seed);

  /// Noise settings, each with N rows (EpuckSwarm's setters, world by world). All or nothing:
  /// a value refused in one world leaves every world as it was.
  void set_ir_noise(const Eigen::Ref<const RowMatrixXd>& probability,
                    const Eigen::Ref<const RowMatrixXd>& mean_m,
                    const Eigen::Ref<const RowMatrixXd>& stddev_m);
  void set_imu_noise(const Eigen::Ref<const RowMatrixXd>& accel_stddev,
                     const Eigen::Ref<const RowMatrixXd>& gyro_stddev);
  void set_imu_bias(const Eigen::Ref<const RowMatrixXd>& accel_bias,
                    const Eigen::Ref<const RowMatrixXd>& gyro_bias);
  void set_slip_noise(const Eigen::Ref<const VectorXd>& stddev);

  /// Steps every world once by dt_s in (0, kMaxStep_s] with wheel commands (N, 2) rad/s, then
  /// fills the output buffers. Everything is checked before any world moves:
  /// std::invalid_argument for a bad dt, shape or a non-finite command.
  void step(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s);

  /// Outputs, (N, ...) as EpuckSwarm's of the same name; references to the buffers.
  const RowMatrixXd& poses() const;
  const RowMatrixXd& velocities() const;
  const RowMatrixXd& wheel_speeds() const;
  const RowMatrixXd& odometry() const;
  const RowMatrixXd& ranges() const;
  const RowMatrixXd& ranges_clean() const;
  const RowMatrixXd& accel() const;
  const RowMatrixXd& gyro() const;
  const VectorXb& in_contact() const;
  /// (B,) steps of each world since it was built or reset.
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> frames() const;

  /// World b's collision world, for queries and rendering; change it only through this class.
  const CollisionWorld& collision_world(int world) const;
  /// World b's swarm, for its other outputs (wheel angles, detected handles and points).
  const EpuckSwarm& swarm(int world) const;

 private:
  struct World {
    std::unique_ptr<CollisionWorld> collision;
    std::unique_ptr<EpuckSwarm> swarm;  // after collision: destroyed first
    std::vector<int> obstacles;
    mutable bool outputs_stale = false; // changed since its rows were last written
  };
  struct NoiseSettings {                // the last accepted settings, N rows each
    RowMatrixXd ir_probability, ir_mean_m, ir_stddev_m, accel_stddev, gyro_stddev, accel_bias,
        gyro_bias;
    VectorXd slip_stddev;
  };

  World& world_at(int world);
  const World& world_at(int world) const;
  Eigen::Index first_row(int world) const { return static_cast<Eigen::Index>(world) * robots_; }
  int add_obstacle(int world, const Vec3& center_m, double yaw_rad, bool box,
                   const Vec3& size, const Vec3& rgb);
  template <typename Apply, typename Restore>
  void for_each_world(Apply apply, Restore restore);
  void write_rows(int world) const;
  void refresh() const;

  int robots_;
  int sensor_count_;
  std::vector<World> worlds_;
  NoiseSettings noise_;
  mutable bool any_stale_ = false;
  // The output buffers, N rows each (mutable: reading refreshes a world changed since its step).
  mutable RowMatrixXd poses_, velocities_, wheel_speeds_, odometry_, ranges_, ranges_clean_,
      accel_, gyro_;
  mutable VectorXb in_contact_;
};

}  // namespace evc
