/// @file
/// N e-pucks advanced together: the per-step work of the simulator in one call.
///
/// A step, per robot in index order: clamp the wheel command and apply slip (diff_drive.hpp),
/// integrate ground truth with the actual speeds and odometry with the commanded ones; then
/// push bodies out of penetration (body_contacts.hpp) and take the ground-truth velocity as the
/// actual displacement over dt; then read the IMU (imu_model.hpp) and the proximity cones
/// (cone_sensor.hpp) with their noise (range_noise.hpp).
///
/// Randomness: each robot owns one generator per noise source (IR, accelerometer, gyroscope,
/// slip), seeded by derive_seed(seed, stream id, source). A robot's stream id is the number of
/// robots added to the swarm before it and stays with the robot when others are removed, so a
/// robot's draws never depend on the other robots, nor on which of them are still there.
/// All noise is off until set.
///
/// Robots can be added and removed between steps. Removal keeps the order of the others, so
/// the rows of every output shift up by one past the removed robot.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "epuck_vrep_compat/epuck/cone_sensor.hpp"
#include "epuck_vrep_compat/epuck/diff_drive.hpp"
#include "epuck_vrep_compat/epuck/epuck_model.hpp"
#include "epuck_vrep_compat/epuck/range_noise.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/body_contacts.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Colour of a robot body in the camera (light grey-white).
inline const Vec3 kRobotBodyRgb{0.9, 0.9, 0.88};
/// Longest step accepted, seconds.
constexpr double kMaxStep_s = 10.0;
/// Largest accelerometer (m/s^2) and gyroscope (rad/s) noise SD accepted.
constexpr double kMaxImuStddev = 1000.0;
/// Largest relative wheel-speed noise SD accepted.
constexpr double kMaxSlipStddev = 1.0;

/// Where EpuckSwarm::write_outputs copies the state: for each output, the first of size()
/// consecutive rows of a caller-owned row-major buffer (a batch of swarms hands in its rows of
/// shared arrays), each row as wide as that output.
struct SwarmOutputRows {
  double* poses;         ///< 3 a row, as poses()
  double* velocities;    ///< 3, as velocities()
  double* wheel_speeds;  ///< 2, as wheel_speeds()
  double* odometry;      ///< 5, as odometry()
  double* ranges;        ///< K, as ranges()
  double* ranges_clean;  ///< K, as ranges_clean()
  double* accel;         ///< 3, as accel()
  double* gyro;          ///< 3, as gyro()
  bool* in_contact;      ///< 1, as in_contact()
};

/// The swarm; it adds its robots' bodies to a CollisionWorld that must outlive it.
class EpuckSwarm {
 public:
  /// Validates @p model (std::invalid_argument).
  EpuckSwarm(CollisionWorld& world, const EpuckModel& model, std::uint64_t seed);
  /// A swarm of @p like's model in another world, sharing with @p like what does not change
  /// (the model, its cones' rays) and the working lists of a step, so that many small swarms
  /// stepped one after the other (BatchedWorlds) keep one copy of them in the cache, not one
  /// each. Swarms that share must never step at the same time.
  EpuckSwarm(CollisionWorld& world, const EpuckSwarm& like, std::uint64_t seed);
  EpuckSwarm(const EpuckSwarm&) = delete;
  EpuckSwarm& operator=(const EpuckSwarm&) = delete;

  /// Adds a robot standing at (x, y) with heading yaw: its body cylinder goes into the world
  /// under @p handle (group ROBOT). Returns the robot's index. Throws std::invalid_argument for
  /// a used handle, |x| or |y| beyond kWorldLimit_m or a non-finite yaw.
  int add_robot(int handle, double x_m, double y_m, double yaw_rad);
  /// Removes robot @p index and its body from the world; the robots after it move up one row
  /// and keep their state and noise streams. Throws std::out_of_range.
  void remove_robot(int index);
  /// Number of robots.
  int size() const { return static_cast<int>(robots_.size()); }
  /// Number of proximity sensors per robot (the model's).
  int sensor_count() const { return static_cast<int>(model_.sensors.size()); }
  /// The model the swarm was built with.
  const EpuckModel& model() const { return model_; }

  /// IR noise per robot and sensor, each (N, K). Throws std::invalid_argument for bad shapes or
  /// values (see validate_range_noise).
  void set_ir_noise(const Eigen::Ref<const RowMatrixXd>& probability,
                    const Eigen::Ref<const RowMatrixXd>& mean_m,
                    const Eigen::Ref<const RowMatrixXd>& stddev_m);
  /// Accelerometer (m/s^2) and gyroscope (rad/s) noise SD per robot and axis, each (N, 3), in
  /// [0, kMaxImuStddev].
  void set_imu_noise(const Eigen::Ref<const RowMatrixXd>& accel_stddev,
                     const Eigen::Ref<const RowMatrixXd>& gyro_stddev);
  /// Constant accelerometer (m/s^2) and gyroscope (rad/s) bias per robot and axis, each (N, 3),
  /// finite with |value| <= kMaxImuStddev (imu_model.hpp's b_a and b_g).
  void set_imu_bias(const Eigen::Ref<const RowMatrixXd>& accel_bias,
                    const Eigen::Ref<const RowMatrixXd>& gyro_bias);
  /// Relative wheel-speed noise SD per robot, (N,), in [0, kMaxSlipStddev].
  void set_slip_noise(const Eigen::Ref<const VectorXd>& stddev);
  /// Restarts every noise stream of every robot from @p seed.
  void reseed(std::uint64_t seed);
  /// Starts the swarm over where its robots stand: frame 0, every noise stream restarted from
  /// @p seed, and each robot as add_robot leaves it at its current pose (odometry there, no
  /// velocity history, wheels at rest and at angle zero, readings as before any step). Robots,
  /// poses and noise settings stay. A run after reset() repeats the run after the robots were
  /// added, bit for bit, when the poses and the world are the same.
  void reset(std::uint64_t seed);

  /// Advances every robot by dt_s in (0, kMaxStep_s] with wheel commands (N, 2) = (left,
  /// right) rad/s; non-finite commands stop the robot (see clamp_wheel_command).
  void step(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s);

  /// Teleports a robot (no contact resolution until the next step); clears its velocity
  /// history so the next IMU reading has no acceleration. Throws std::out_of_range.
  void set_pose(int index, double x_m, double y_m, double yaw_rad);
  /// Overwrites a robot's odometry pose. Throws std::out_of_range.
  void set_odometry(int index, double x_m, double y_m, double yaw_rad);

  /// (N, 3) x, y, yaw ground truth.
  RowMatrixXd poses() const;
  /// (N, 3) vx, vy (world frame, m/s), yaw rate (rad/s).
  RowMatrixXd velocities() const;
  /// (N, 2) applied wheel speeds (after clamp and slip), rad/s.
  RowMatrixXd wheel_speeds() const;
  /// (N, 2) cumulative wheel angles, rad.
  RowMatrixXd wheel_angles() const;
  /// (N, 5) odometry x, y, yaw, v, w (from commanded wheel speeds).
  RowMatrixXd odometry() const;
  /// (N, K) clean readings in [min, max]; nothing detected reads max_range_m.
  RowMatrixXd ranges_clean() const;
  /// (N, K) noisy readings.
  RowMatrixXd ranges() const;
  /// (N, K) handle detected by each sensor, -1 for none.
  RowMatrixXi detected_handles() const;
  /// (N*K, 3) detected points, sensor frame, zero for none (row = robot * K + sensor).
  RowMatrixXd detected_points() const;
  /// (N*K, 3) surface normals at the detected points, sensor frame, zero for none.
  RowMatrixXd detected_normals() const;
  /// (N, 3) accelerometer, body frame, m/s^2.
  RowMatrixXd accel() const;
  /// (N, 3) gyroscope, body frame, rad/s.
  RowMatrixXd gyro() const;
  /// (N,) true for a robot that was in a penetrating contact (an obstacle, another robot)
  /// during the last step's contact resolution (body_contacts.hpp), false before any step.
  VectorXb in_contact() const;
  /// Copies poses, velocities, wheel speeds, odometry, ranges, clean ranges, accelerometer,
  /// gyroscope and contacts into the rows @p out points at, in one pass over the robots.
  /// Allocates nothing.
  void write_outputs(const SwarmOutputRows& out) const;
  /// (N,) body handles.
  VectorXi handles() const;
  /// (N,) noise stream ids (see the file comment).
  std::vector<std::uint64_t> stream_ids() const;
  /// Steps taken.
  std::int64_t frame() const { return frame_; }

 private:
  // A sensor's detection, read by detected_handles, _points and _normals (not by the step's
  // outputs, so kept apart from the readings).
  struct Detection {
    int handle = -1;
    Vec3 point_m = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
  };
  // What every step reads and writes of a robot, in four cache lines: a batch of small worlds
  // touches each world's robots once a step, so the fewer lines, the fewer misses.
  struct alignas(64) Robot {
    int handle = -1;
    bool has_velocity = false;     // false until a step after add or teleport
    bool ir_noise_on = false;      // some sensor's noise probability is above zero
    bool sensors_blank = false;    // every sensor reads nothing, as clear_sensors leaves it
    bool in_contact = false;
    bool accel_noise_on = false;   // some axis's SD is above zero (RobotNoise)
    bool gyro_noise_on = false;
    bool slip_on = false;          // RobotNoise::slip_stddev > 0
    Pose2 pose;
    Pose2 odometry;
    Twist2 odometry_twist;
    Twist2 twist;                  // the body's, from wheel_speed (the last step's)
    Vec3 velocity = Vec3::Zero();  // vx, vy, yaw rate
    WheelPair wheel_speed;
    WheelPair wheel_angle;
    Vec3 accel = Vec3::Zero();
    Vec3 gyro = Vec3::Zero();
    Vec3 accel_bias = Vec3::Zero();
    Vec3 gyro_bias = Vec3::Zero();
    std::uint64_t ir_draws_owed = 0;  // IR draws skipped since ir_rng was seeded (see step)
  };
  // A robot's noise streams and settings, read by a step only where noise is on.
  struct RobotNoise {
    std::uint64_t stream = 0;      // derive_seed's index: the robot's own noise streams
    Vec3 accel_stddev = Vec3::Zero();
    Vec3 gyro_stddev = Vec3::Zero();
    double slip_stddev = 0.0;
    std::vector<RangeNoise> ir;
    Rng ir_rng, accel_rng, gyro_rng, slip_rng;
  };

  Robot& robot_at(int index);
  void seed_streams(Robot& robot, RobotNoise& noise) const;
  void clear_motion(Robot& robot) const;
  void clear_sensors(std::size_t index);
  Pose body_pose(const Pose2& pose) const;
  void move_robots(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s);
  void read_imu(std::size_t index, const Vec3& velocity, double yaw_at_start_rad, double dt_s);
  using NearbyIterator = std::vector<const Body*>::const_iterator;
  void find_nearby(bool world_changed);
  void find_nearby_among(const std::vector<const Body*>& bodies, double reach_m);
  void read_proximity(std::size_t index, const Quat& heading, NearbyIterator begin,
                      NearbyIterator end);
  template <typename Get>
  RowMatrixXd per_robot(int columns, Get get) const;
  template <typename Get>
  RowMatrixXd per_sensor_vector(Get get) const;
  RowMatrixXd sensor_values(const std::vector<double>& readings) const;

  struct BodyBox {                                 // a body's box in the plane
    Eigen::Vector2d low_m, high_m;
    const Body* body;
    int handle;                                    // body's
  };
  struct Shared;  // the model, its rays and a step's scratch, shared by swarms of one model
  EpuckSwarm(CollisionWorld& world, std::shared_ptr<Shared> shared, std::uint64_t seed);
  static std::shared_ptr<Shared> share(const EpuckModel& model);

  CollisionWorld& world_;
  std::shared_ptr<Shared> shared_;
  // Shared_'s, by name (see Shared).
  const EpuckModel& model_;
  const std::vector<std::vector<Vec3>>& ray_directions_;  // per sensor, sensor frame
  const std::vector<Quat>& sensor_orientations_;          // per sensor, sensor to body
  const std::vector<Vec3>& sensor_axes_;                  // per sensor, its axis in the body
  ConeReader& cone_reader_;
  std::vector<ConeCandidate>& candidates_;          // one robot's, for its cones
  std::vector<BodyBox>& body_boxes_;                // of find_nearby_among
  std::vector<Pose2>& start_;                       // of step(): poses at its start
  std::vector<MovableBody>& bodies_;                // of step(): bodies to resolve
  std::vector<char>& touched_;                      // of step(): contacts found
  double sensor_reach_m_ = 0.0;   // how far from the robot's vertical axis a cone reaches
  double sensor_z_min_m_ = 0.0;   // lowest and highest points a cone reaches
  double sensor_z_max_m_ = 0.0;
  double sensor_height_m_ = 0.0;  // the first sensor's height above the ground
  double sensor_ball_m_ = 0.0;    // how far a cone reaches from the robot's axis at that height
  std::uint64_t seed_;
  std::vector<Robot> robots_;
  std::vector<RobotNoise> noise_;  // per robot, as robots_
  // Per robot and sensor, row i * K + k: the readings every step copies out, contiguous.
  std::vector<double> clean_m_, noisy_m_;
  std::vector<Detection> detections_;
  std::uint64_t next_stream_ = 0;  // stream id of the next robot added
  std::int64_t frame_ = 0;
  ContactCache contact_cache_;     // the contact neighbour lists, from one step to the next
  // What each robot's cones may see (find_nearby), kept from one step to the next.
  bool nearby_valid_ = false;      // a step completed, leaving the world at revision_seen_
  std::uint64_t revision_seen_ = 0;
  std::vector<std::size_t> nearby_first_;  // robot i's: nearby_[first[i], first[i + 1])
  std::vector<const Body*> nearby_;
  std::vector<Eigen::Vector2d> nearby_anchor_m_;  // each robot's x, y when they were found
};

}  // namespace evc
