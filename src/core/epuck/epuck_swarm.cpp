#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "epuck_vrep_compat/epuck/cone_sensor.hpp"
#include "epuck_vrep_compat/epuck/imu_model.hpp"
#include "epuck_vrep_compat/world/body_contacts.hpp"
#include "epuck/shape_checks.hpp"
#include "world/body.hpp"

namespace evc {
namespace {

// Stream ids of derive_seed; fixed forever, since changing one changes every replay.
enum Stream : std::uint64_t { kStreamIr = 1, kStreamAccel = 2, kStreamGyro = 3, kStreamSlip = 4 };

// The IR cones see everything a robot can bump into, never the floor under it.
constexpr int kSensorMask = kGroupStatic | kGroupRobot | kGroupDynamic;
// How far beyond its cones' reach a robot's list of what they may see extends; the lists
// last until some robot has moved half of it. Among many robots one of them soon has, and
// every list is built again: there a wider margin, fewer rebuilds (each a box query and a
// broadphase update of every moved body) for longer lists (a cheap distance check each);
// counted by callgrind, the wider margin costs more in worlds of 10 robots or fewer.
constexpr double kNearbyMargin_m = 0.03;
constexpr double kCrowdNearbyMargin_m = 0.06;
constexpr std::size_t kCrowd = 100;  // robots in a world from which the wider margin is used

// Standard deviations must be in [0, limit]: a huge finite one (1e308) would carry inf into
// the pose or the readings as surely as inf itself.
void check_stddev(const Eigen::Ref<const RowMatrixXd>& values, double limit, const char* name) {
  if (!((values.array() >= 0.0) && (values.array() <= limit)).all()) {
    throw std::invalid_argument(std::string(name) + " must be in [0, " + std::to_string(limit) +
                                "]");
  }
}

// Whether two doubles are the same bits (unlike ==, which takes -0.0 for 0.0).
bool same_bits(double a, double b) {
  std::uint64_t a_bits, b_bits;
  std::memcpy(&a_bits, &a, sizeof a);
  std::memcpy(&b_bits, &b, sizeof b);
  return a_bits == b_bits;
}

void check_planar_pose(double x_m, double y_m, double yaw_rad) {
  if (!(std::abs(x_m) <= kWorldLimit_m && std::abs(y_m) <= kWorldLimit_m) ||
      !std::isfinite(yaw_rad)) {
    throw std::invalid_argument("x and y must be within ±1e6 m and yaw finite");
  }
}

}  // namespace

// What swarms of one model share: the model and its cones' rays, which never change, and the
// working lists of a step, which hold nothing from one step to the next (each step fills them
// before reading them), so that a swarm may step with lists another swarm left.
struct EpuckSwarm::Shared {
  explicit Shared(const EpuckModel& m) : model(m) {
    for (const ConeSensor& sensor : model.sensors) {
      ray_directions.push_back(cone_ray_directions(sensor));
      sensor_orientations.push_back(sensor_orientation(sensor));
      sensor_axes.push_back(sensor_orientations.back() * Vec3::UnitX());
    }
  }
  const EpuckModel model;
  std::vector<std::vector<Vec3>> ray_directions;
  std::vector<Quat> sensor_orientations;
  std::vector<Vec3> sensor_axes;  // each cone's axis, body frame
  ConeReader cone_reader;
  std::vector<ConeCandidate> candidates;
  std::vector<BodyBox> body_boxes;
  std::vector<Pose2> start;
  std::vector<MovableBody> bodies;
  std::vector<char> touched;
  ContactCache contacts;  // its working lists, which every sharing swarm's cache uses
};

std::shared_ptr<EpuckSwarm::Shared> EpuckSwarm::share(const EpuckModel& model) {
  validate_epuck_model(model);
  return std::make_shared<Shared>(model);
}

EpuckSwarm::EpuckSwarm(CollisionWorld& world, const EpuckModel& model, std::uint64_t seed)
    : EpuckSwarm(world, share(model), seed) {}

EpuckSwarm::EpuckSwarm(CollisionWorld& world, const EpuckSwarm& like, std::uint64_t seed)
    : EpuckSwarm(world, like.shared_, seed) {}

EpuckSwarm::EpuckSwarm(CollisionWorld& world, std::shared_ptr<Shared> shared, std::uint64_t seed)
    : world_(world), shared_(std::move(shared)), model_(shared_->model),
      ray_directions_(shared_->ray_directions), sensor_orientations_(shared_->sensor_orientations),
      sensor_axes_(shared_->sensor_axes),
      cone_reader_(shared_->cone_reader), candidates_(shared_->candidates),
      body_boxes_(shared_->body_boxes), start_(shared_->start), bodies_(shared_->bodies),
      touched_(shared_->touched), seed_(seed) {
  static_assert(sizeof(Robot) == 4 * 64, "a robot's per-step state fills four cache lines");
  contact_cache_.share_scratch(shared_->contacts);
  sensor_z_min_m_ = model_.sensors.front().position_m.z();
  sensor_z_max_m_ = sensor_z_min_m_;
  for (const ConeSensor& sensor : model_.sensors) {
    sensor_reach_m_ =
        std::max(sensor_reach_m_, sensor.position_m.head<2>().norm() + sensor.max_range_m);
    sensor_z_min_m_ = std::min(sensor_z_min_m_, sensor.position_m.z() - sensor.max_range_m);
    sensor_z_max_m_ = std::max(sensor_z_max_m_, sensor.position_m.z() + sensor.max_range_m);
  }
  sensor_height_m_ = model_.sensors.front().position_m.z();
  for (const ConeSensor& sensor : model_.sensors) {
    const Vec3 from_axis = sensor.position_m - Vec3(0.0, 0.0, sensor_height_m_);
    sensor_ball_m_ = std::max(sensor_ball_m_, from_axis.norm() + sensor.max_range_m);
  }
}

int EpuckSwarm::add_robot(int handle, double x_m, double y_m, double yaw_rad) {
  check_planar_pose(x_m, y_m, yaw_rad);
  Robot robot;
  robot.handle = handle;
  robot.pose = Pose2{x_m, y_m, wrap_angle(yaw_rad)};
  clear_motion(robot);
  RobotNoise noise;
  noise.ir.assign(model_.sensors.size(), RangeNoise());
  noise.stream = next_stream_;
  seed_streams(robot, noise);
  world_.add_cylinder(handle, model_.body_radius_m, model_.body_height_m, body_pose(robot.pose),
                      kRobotBodyRgb, kGroupRobot);
  ++next_stream_;  // only once the body is in: a refused robot takes no stream
  robots_.push_back(robot);
  noise_.push_back(std::move(noise));
  const std::size_t readings = robots_.size() * model_.sensors.size();
  clean_m_.resize(readings);
  noisy_m_.resize(readings);
  detections_.resize(readings);
  clear_sensors(robots_.size() - 1);
  return size() - 1;
}

// Everything of a robot that a step changes, other than its pose and its readings
// (clear_sensors), as a robot just added at that pose has it.
void EpuckSwarm::clear_motion(Robot& robot) const {
  robot.odometry = robot.pose;
  robot.odometry_twist = Twist2();
  robot.velocity.setZero();
  robot.has_velocity = false;
  robot.wheel_speed = WheelPair();
  robot.wheel_angle = WheelPair();
  robot.accel = Vec3(0.0, 0.0, model_.gravity_m_s2);
  robot.gyro.setZero();
  robot.in_contact = false;
}

// Every cone of robot @p index reads nothing: no handle, no point, the maximum range.
void EpuckSwarm::clear_sensors(std::size_t index) {
  const std::size_t first = index * model_.sensors.size();
  for (std::size_t k = 0; k < model_.sensors.size(); ++k) {
    clean_m_[first + k] = noisy_m_[first + k] = model_.sensors[k].max_range_m;
    detections_[first + k] = Detection();
  }
  robots_[index].sensors_blank = true;
}

void EpuckSwarm::remove_robot(int index) {
  const Robot& robot = robot_at(index);
  // A body someone already took out of the world must not keep the robot in the swarm.
  if (world_.has(robot.handle)) world_.remove(robot.handle);
  robots_.erase(robots_.begin() + index);
  noise_.erase(noise_.begin() + index);
  const auto first = static_cast<std::ptrdiff_t>(index * model_.sensors.size());
  const auto last = first + static_cast<std::ptrdiff_t>(model_.sensors.size());
  clean_m_.erase(clean_m_.begin() + first, clean_m_.begin() + last);
  noisy_m_.erase(noisy_m_.begin() + first, noisy_m_.begin() + last);
  detections_.erase(detections_.begin() + first, detections_.begin() + last);
}

void EpuckSwarm::seed_streams(Robot& robot, RobotNoise& noise) const {
  noise.ir_rng = Rng(derive_seed(seed_, noise.stream, kStreamIr));
  robot.ir_draws_owed = 0;
  noise.accel_rng = Rng(derive_seed(seed_, noise.stream, kStreamAccel));
  noise.gyro_rng = Rng(derive_seed(seed_, noise.stream, kStreamGyro));
  noise.slip_rng = Rng(derive_seed(seed_, noise.stream, kStreamSlip));
}

void EpuckSwarm::reseed(std::uint64_t seed) {
  seed_ = seed;
  for (std::size_t i = 0; i < robots_.size(); ++i) seed_streams(robots_[i], noise_[i]);
}

void EpuckSwarm::reset(std::uint64_t seed) {
  reseed(seed);
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    clear_motion(robots_[i]);
    clear_sensors(i);
  }
  frame_ = 0;
  // What the last steps kept about the world goes too, so the next step finds it as the
  // first step after the robots were added did.
  nearby_valid_ = false;
  contact_cache_.clear();
}

Pose EpuckSwarm::body_pose(const Pose2& pose) const {
  return Pose{Vec3(pose.x_m, pose.y_m, 0.5 * model_.body_height_m),
              Quat(Eigen::AngleAxisd(pose.yaw_rad, Vec3::UnitZ()))};
}

EpuckSwarm::Robot& EpuckSwarm::robot_at(int index) {
  if (index < 0 || index >= size()) {
    throw std::out_of_range("robot index " + std::to_string(index) + " out of range");
  }
  return robots_[static_cast<std::size_t>(index)];
}

void EpuckSwarm::set_ir_noise(const Eigen::Ref<const RowMatrixXd>& probability,
                              const Eigen::Ref<const RowMatrixXd>& mean_m,
                              const Eigen::Ref<const RowMatrixXd>& stddev_m) {
  check_shape(probability, size(), sensor_count(), "probability");
  check_shape(mean_m, size(), sensor_count(), "mean_m");
  check_shape(stddev_m, size(), sensor_count(), "stddev_m");
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) {
      const ConeSensor& sensor = model_.sensors[k];
      validate_range_noise({probability(i, k), mean_m(i, k), stddev_m(i, k)},
                           sensor.min_range_m, sensor.max_range_m);
    }
  }
  for (int i = 0; i < size(); ++i) {
    robots_[i].ir_noise_on = false;
    for (int k = 0; k < sensor_count(); ++k) {
      noise_[i].ir[k] = RangeNoise{probability(i, k), mean_m(i, k), stddev_m(i, k)};
      robots_[i].ir_noise_on = robots_[i].ir_noise_on || probability(i, k) > 0.0;
    }
  }
}

void EpuckSwarm::set_imu_noise(const Eigen::Ref<const RowMatrixXd>& accel_stddev,
                               const Eigen::Ref<const RowMatrixXd>& gyro_stddev) {
  check_shape(accel_stddev, size(), 3, "accel_stddev");
  check_shape(gyro_stddev, size(), 3, "gyro_stddev");
  check_stddev(accel_stddev, kMaxImuStddev, "accel_stddev");
  check_stddev(gyro_stddev, kMaxImuStddev, "gyro_stddev");
  for (int i = 0; i < size(); ++i) {
    noise_[i].accel_stddev = accel_stddev.row(i).transpose();
    noise_[i].gyro_stddev = gyro_stddev.row(i).transpose();
    robots_[i].accel_noise_on = !noise_[i].accel_stddev.isZero(0.0);
    robots_[i].gyro_noise_on = !noise_[i].gyro_stddev.isZero(0.0);
  }
}

void EpuckSwarm::set_imu_bias(const Eigen::Ref<const RowMatrixXd>& accel_bias,
                              const Eigen::Ref<const RowMatrixXd>& gyro_bias) {
  check_shape(accel_bias, size(), 3, "accel_bias");
  check_shape(gyro_bias, size(), 3, "gyro_bias");
  check_stddev(accel_bias.cwiseAbs(), kMaxImuStddev, "|accel_bias|");
  check_stddev(gyro_bias.cwiseAbs(), kMaxImuStddev, "|gyro_bias|");
  for (int i = 0; i < size(); ++i) {
    robots_[i].accel_bias = accel_bias.row(i).transpose();
    robots_[i].gyro_bias = gyro_bias.row(i).transpose();
  }
}

void EpuckSwarm::set_slip_noise(const Eigen::Ref<const VectorXd>& stddev) {
  check_length(stddev.size(), size(), "stddev");
  check_stddev(stddev.transpose(), kMaxSlipStddev, "stddev");
  for (int i = 0; i < size(); ++i) {
    noise_[i].slip_stddev = stddev[i];
    robots_[i].slip_on = stddev[i] > 0.0;
  }
}

void EpuckSwarm::set_pose(int index, double x_m, double y_m, double yaw_rad) {
  check_planar_pose(x_m, y_m, yaw_rad);
  Robot& robot = robot_at(index);
  robot.pose = Pose2{x_m, y_m, wrap_angle(yaw_rad)};
  robot.velocity.setZero();
  robot.has_velocity = false;
  world_.set_pose(robot.handle, body_pose(robot.pose));
}

void EpuckSwarm::set_odometry(int index, double x_m, double y_m, double yaw_rad) {
  check_planar_pose(x_m, y_m, yaw_rad);
  robot_at(index).odometry = Pose2{x_m, y_m, wrap_angle(yaw_rad)};
}

void EpuckSwarm::step(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s) {
  if (!(dt_s > 0.0 && dt_s <= kMaxStep_s)) throw std::invalid_argument("dt_s must be in (0, 10]");
  check_shape(wheel_cmd_rad_s, size(), 2, "wheel_cmd");
  // Whether anybody else changed the world since the last step: then what the last step kept
  // about it (the contact lists, what the cones may see) must be found again.
  const bool world_changed = !nearby_valid_ || world_.revision() != revision_seen_;
  // Fail before changing anything if someone removed a robot body from the world (which
  // changes its revision: a world that did not change still holds them all).
  for (std::size_t i = 0; world_changed && i < robots_.size(); ++i) {
    if (!world_.has(robots_[i].handle)) {
      throw UnknownHandle("robot body " + std::to_string(robots_[i].handle) +
                          " was removed from the world");
    }
  }
  nearby_valid_ = false;  // until this step completes
  std::vector<Pose2>& start = start_;
  start.resize(robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) start[i] = robots_[i].pose;
  move_robots(dt_s, wheel_cmd_rad_s);

  bodies_.clear();
  for (const Robot& robot : robots_) bodies_.push_back({robot.handle, body_pose(robot.pose)});
  resolve_penetrations(world_, bodies_, ContactSettings(), &contact_cache_, &touched_);
  world_.maintain_broadphase();
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    robots_[i].pose.x_m = bodies_[i].pose.position_m.x();
    robots_[i].pose.y_m = bodies_[i].pose.position_m.y();
    robots_[i].in_contact = touched_[i] != 0;
  }

  find_nearby(world_changed);
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    Robot& robot = robots_[i];
    const Vec3 velocity((robot.pose.x_m - start[i].x_m) / dt_s,
                        (robot.pose.y_m - start[i].y_m) / dt_s, robot.twist.w_rad_s);
    read_imu(i, velocity, start[i].yaw_rad, dt_s);
    // The body's orientation is the robot's heading: contacts moved the body, never turned it.
    read_proximity(i, bodies_[i].pose.orientation, nearby_.begin() + nearby_first_[i],
                   nearby_.begin() + nearby_first_[i + 1]);
  }
  revision_seen_ = world_.revision();
  nearby_valid_ = true;
  ++frame_;
}

void EpuckSwarm::move_robots(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s) {
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    Robot& robot = robots_[i];
    const WheelPair command = clamp_wheel_command(
        {wheel_cmd_rad_s(i, 0), wheel_cmd_rad_s(i, 1)}, model_.max_wheel_speed_rad_s);
    // Without slip no draw, and the wheels turn as commanded (apply_wheel_slip).
    robot.wheel_speed =
        robot.slip_on ? apply_wheel_slip(command, noise_[i].slip_stddev, noise_[i].slip_rng)
                      : command;
    robot.wheel_angle.left += robot.wheel_speed.left * dt_s;
    robot.wheel_angle.right += robot.wheel_speed.right * dt_s;
    const Twist2 actual =
        body_twist(robot.wheel_speed, model_.wheel_radius_m, model_.wheel_separation_m);
    robot.twist = actual;
    // Without slip the wheels turn as commanded: odometry's twist is the same, bit for bit.
    robot.odometry_twist = !robot.slip_on ? actual
                           : body_twist(command, model_.wheel_radius_m, model_.wheel_separation_m);
    // Odometry that shares the heading and the twist moves along the same arc (contacts never
    // turn a robot, so they share it until slip or set_odometry parts them).
    const bool same_arc = same_bits(robot.odometry.yaw_rad, robot.pose.yaw_rad) &&
                          same_bits(robot.odometry_twist.v_m_s, actual.v_m_s) &&
                          same_bits(robot.odometry_twist.w_rad_s, actual.w_rad_s);
    const ArcMove move = arc_move(robot.pose.yaw_rad, actual, dt_s);
    robot.pose = apply_arc(robot.pose, move);
    robot.odometry = same_arc ? apply_arc(robot.odometry, move)
                              : integrate_arc(robot.odometry, robot.odometry_twist, dt_s);
  }
}

void EpuckSwarm::read_imu(std::size_t index, const Vec3& velocity, double yaw_at_start_rad,
                          double dt_s) {
  Robot& robot = robots_[index];
  Vec3 accel_world = Vec3::Zero();
  if (robot.has_velocity) {
    accel_world.head<2>() = (velocity.head<2>() - robot.velocity.head<2>()) / dt_s;
  }
  robot.velocity = velocity;
  robot.has_velocity = true;
  // The velocities are chords of the previous and this step, so their difference belongs to
  // the instant between them: the start of this step, and the heading the robot had then.
  const Vec3 force = specific_force(accel_world, yaw_at_start_rad, model_.gravity_m_s2);
  // An axis without noise draws nothing and adds nothing (add_axis_noise).
  robot.accel = force + robot.accel_bias;
  if (robot.accel_noise_on) {
    robot.accel = add_axis_noise(robot.accel, noise_[index].accel_stddev, noise_[index].accel_rng);
  }
  robot.gyro = Vec3(0.0, 0.0, velocity.z()) + robot.gyro_bias;
  if (robot.gyro_noise_on) {
    robot.gyro = add_axis_noise(robot.gyro, noise_[index].gyro_stddev, noise_[index].gyro_rng);
  }
}

// What each robot's cones may see: what lies in the box its cones can reach, widened by a
// margin and queried for all robots in one batch. The lists are kept from step to step, like
// the contact lists (a Verlet list): they hold while nobody else changed the world and no
// robot has drifted half the margin since, since two robots then close at most the margin,
// and a robot's body (an upright cylinder) is the same set of points at any heading. Extra
// candidates change no reading (see ConeReader::read).
void EpuckSwarm::find_nearby(bool world_changed) {
  bool rebuild = world_changed || nearby_anchor_m_.size() != robots_.size();
  const double margin_m = robots_.size() > kCrowd ? kCrowdNearbyMargin_m : kNearbyMargin_m;
  const double limit_squared = 0.25 * margin_m * margin_m;
  for (std::size_t i = 0; !rebuild && i < robots_.size(); ++i) {
    const Eigen::Vector2d drift(robots_[i].pose.x_m - nearby_anchor_m_[i].x(),
                                robots_[i].pose.y_m - nearby_anchor_m_[i].y());
    rebuild = drift.squaredNorm() > limit_squared;
  }
  if (!rebuild) return;
  const double reach_m = sensor_reach_m_ + margin_m;
  nearby_anchor_m_.resize(robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    nearby_anchor_m_[i] = Eigen::Vector2d(robots_[i].pose.x_m, robots_[i].pose.y_m);
  }
  const std::vector<const Body*>& bodies = world_.bodies_in_handle_order();
  if (bodies.size() <= kSmallWorld) {
    find_nearby_among(bodies, reach_m);
    return;
  }
  std::vector<BoxQuery> boxes;
  boxes.reserve(robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const Pose2& pose = robots_[i].pose;
    boxes.push_back(BoxQuery{Vec3(pose.x_m - reach_m, pose.y_m - reach_m, sensor_z_min_m_),
                             Vec3(pose.x_m + reach_m, pose.y_m + reach_m, sensor_z_max_m_),
                             robots_[i].handle});
  }
  overlap_query_batch(world_, boxes, kSensorMask, nearby_first_, nearby_);
}

// find_nearby in a small world (@p bodies, in handle order): every body's box against every
// robot's, without the broadphase, whose boxes then need no update. The boxes are those the
// broadphase would hold, less its fattening (Bullet's getAabb of each shape where it is); a
// robot's is its cones' reach widened by the margin, as find_nearby queries it.
void EpuckSwarm::find_nearby_among(const std::vector<const Body*>& bodies, double reach_m) {
  body_boxes_.clear();
  for (const Body* body : bodies) {
    if ((body->group & kSensorMask) == 0) continue;
    btVector3 low, high;
    body->shape->getAabb(body->object->getWorldTransform(), low, high);
    if (low.z() > sensor_z_max_m_ || high.z() < sensor_z_min_m_) continue;
    body_boxes_.push_back(BodyBox{Eigen::Vector2d(low.x(), low.y()),
                                  Eigen::Vector2d(high.x(), high.y()), body, body->handle});
  }
  nearby_first_.assign(robots_.size() + 1, 0);
  nearby_.clear();
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const Pose2& pose = robots_[i].pose;
    const double low_x = pose.x_m - reach_m, high_x = pose.x_m + reach_m;
    const double low_y = pose.y_m - reach_m, high_y = pose.y_m + reach_m;
    const int self = robots_[i].handle;
    for (const BodyBox& box : body_boxes_) {
      // All five tests, without branching on each (which mispredicts half the time).
      const bool apart = (box.low_m.x() > high_x) | (box.high_m.x() < low_x) |
                         (box.low_m.y() > high_y) | (box.high_m.y() < low_y) |
                         (box.handle == self);
      if (!apart) nearby_.push_back(box.body);
    }
    nearby_first_[i + 1] = nearby_.size();
  }
}

// [@p begin, @p end): what the robot's cones may see (from find_nearby); of these, only what
// may lie within reach of one of its cones is handed to them. @p heading: the robot's yaw as a
// rotation about z (its body's orientation, body_pose).
void EpuckSwarm::read_proximity(std::size_t index, const Quat& heading, NearbyIterator begin,
                                NearbyIterator end) {
  Robot& robot = robots_[index];
  const Pose2& pose = robot.pose;
  candidates_.clear();
  const Vec3 viewpoint(pose.x_m, pose.y_m, sensor_height_m_);
  for (NearbyIterator it = begin; it != end; ++it) {
    ConeCandidate candidate = cone_candidate(**it);
    // Slack: a body that rounding puts on the edge is kept, never dropped.
    const double reach_m = sensor_reach_m_ + candidate.radius_m + 1e-9;
    const double dx = candidate.centre_m.x() - pose.x_m, dy = candidate.centre_m.y() - pose.y_m;
    if (dx * dx + dy * dy > reach_m * reach_m ||
        candidate.centre_m.z() - candidate.radius_m > sensor_z_max_m_ + 1e-9 ||
        candidate.centre_m.z() + candidate.radius_m < sensor_z_min_m_ - 1e-9) {
      continue;
    }
    // A body whose closest point lies beyond every cone's reach from the robot (a wall whose
    // enclosing sphere is large but which stands farther away) cannot be seen either.
    // Its half-space, seen from the same point, spares the cones that face away from it.
    if (bound_candidate(candidate, viewpoint) > sensor_ball_m_ + 1e-9) continue;
    candidates_.push_back(candidate);
  }
  if (candidates_.empty() && !robot.ir_noise_on) {
    // Nothing nearby and no noise: every cone reads nothing, as clear_motion leaves it, and
    // every IR draw is owed (as below, sensor by sensor).
    if (!robot.sensors_blank) clear_sensors(index);
    robot.ir_draws_owed += model_.sensors.size();
    return;
  }
  robot.sensors_blank = false;
  const Vec3 centre(pose.x_m, pose.y_m, 0.0);
  // The cull needs each cone's frame only to rounding (ConeReader::cull): the heading's
  // matrix gives it for a few products; the exact frame (a quaternion product and rotation,
  // whose bits reach the readings) only for a cone that something may reach into.
  const Eigen::Matrix3d turn = heading.toRotationMatrix();
  const std::size_t first = index * model_.sensors.size();
  RobotNoise& noise_streams = noise_[index];
  for (std::size_t k = 0; k < model_.sensors.size(); ++k) {
    const ConeSensor& sensor = model_.sensors[k];
    Detection& out = detections_[first + k];
    double& clean_m = clean_m_[first + k];
    double& noisy_m = noisy_m_[first + k];
    if (candidates_.empty()) {  // nothing nearby: skip all ray work
      out = Detection();
      clean_m = sensor.max_range_m;
    } else {
      ConeReading reading;
      if (cone_reader_.cull(candidates_, centre + turn * sensor.position_m,
                            turn * sensor_axes_[k], sensor)) {
        const Pose sensor_pose{centre + heading * sensor.position_m,
                               heading * sensor_orientations_[k]};
        reading = cone_reader_.read_culled(sensor_pose, sensor, ray_directions_[k]);
      }
      out.handle = reading.handle;
      out.point_m = reading.point_m;
      out.normal = reading.normal;
      clean_m = reading.handle < 0
                        ? sensor.max_range_m
                        : std::clamp(reading.distance_m, sensor.min_range_m, sensor.max_range_m);
    }
    const RangeNoise& noise = noise_streams.ir[k];
    if (noise.probability <= 0.0) {
      // The draw could not make the reading noisy (it is in (0, 1]): it is owed instead, and
      // made before the next draw that can, so every later draw is the one it would have been.
      ++robot.ir_draws_owed;
      noisy_m = std::clamp(clean_m, sensor.min_range_m, sensor.max_range_m);
      continue;
    }
    noise_streams.ir_rng.discard(robot.ir_draws_owed);
    robot.ir_draws_owed = 0;
    bool applied = false;
    noisy_m = apply_range_noise(clean_m, sensor.min_range_m, sensor.max_range_m, noise,
                                noise_streams.ir_rng, applied);
  }
}

}  // namespace evc
