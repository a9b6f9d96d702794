#include "epuck_vrep_compat/epuck/batched_worlds.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "epuck/shape_checks.hpp"

namespace evc {
namespace {

// The robots' start grid: cells of this side, as many columns as rows about the origin.
constexpr double kStartCell_m = 0.1;

}  // namespace

BatchedWorlds::BatchedWorlds(const EpuckModel& model, int worlds, int robots,
                             const std::vector<std::uint64_t>& seeds)
    : robots_(robots), sensor_count_(static_cast<int>(model.sensors.size())) {
  if (worlds < 1 || robots < 1 ||
      static_cast<std::int64_t>(worlds) * robots > kMaxRobots) {
    throw std::invalid_argument("worlds and robots must be >= 1, with worlds * robots <= " +
                                std::to_string(kMaxRobots));
  }
  if (seeds.size() != static_cast<std::size_t>(worlds)) {
    throw std::invalid_argument("seeds must hold one seed per world (" + std::to_string(worlds) +
                                "), not " + std::to_string(seeds.size()));
  }
  validate_epuck_model(model);
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
  const double offset_m = 0.5 * kStartCell_m * (columns - 1);
  worlds_.resize(static_cast<std::size_t>(worlds));
  for (int b = 0; b < worlds; ++b) {
    World& world = worlds_[b];
    world.collision = std::make_unique<CollisionWorld>();
    // Every world's swarm shares the first's model, rays and scratch (they step in turn).
    world.swarm = b == 0 ? std::make_unique<EpuckSwarm>(*world.collision, model, seeds[b])
                         : std::make_unique<EpuckSwarm>(*world.collision, *worlds_[0].swarm,
                                                        seeds[b]);
    for (int r = 0; r < robots; ++r) {
      world.swarm->add_robot(kRobotHandleBase + r, kStartCell_m * (r % columns) - offset_m,
                             kStartCell_m * (r / columns) - offset_m, 0.0);
    }
  }
  const Eigen::Index n = size();
  noise_.ir_probability = noise_.ir_mean_m = noise_.ir_stddev_m =
      RowMatrixXd::Zero(n, sensor_count_);
  noise_.accel_stddev = noise_.gyro_stddev = noise_.accel_bias = noise_.gyro_bias =
      RowMatrixXd::Zero(n, 3);
  noise_.slip_stddev = VectorXd::Zero(n);
  poses_.resize(n, 3);
  velocities_.resize(n, 3);
  wheel_speeds_.resize(n, 2);
  odometry_.resize(n, 5);
  ranges_.resize(n, sensor_count_);
  ranges_clean_.resize(n, sensor_count_);
  accel_.resize(n, 3);
  gyro_.resize(n, 3);
  in_contact_.resize(n);
  for (int b = 0; b < worlds; ++b) write_rows(b);
}

BatchedWorlds::~BatchedWorlds() = default;

BatchedWorlds::World& BatchedWorlds::world_at(int world) {
  if (world < 0 || world >= worlds()) {
    throw std::out_of_range("world index " + std::to_string(world) + " out of range [0, " +
                            std::to_string(worlds()) + ")");
  }
  return worlds_[static_cast<std::size_t>(world)];
}

const BatchedWorlds::World& BatchedWorlds::world_at(int world) const {
  return const_cast<BatchedWorlds*>(this)->world_at(world);
}

int BatchedWorlds::add_box(int world, const Vec3& center_m, const Vec3& half_extents_m,
                           double yaw_rad, const Vec3& rgb) {
  return add_obstacle(world, center_m, yaw_rad, true, half_extents_m, rgb);
}

int BatchedWorlds::add_cylinder(int world, const Vec3& center_m, double radius_m,
                                double height_m, const Vec3& rgb) {
  return add_obstacle(world, center_m, 0.0, false, Vec3(radius_m, height_m, 0.0), rgb);
}

// A box of half extents @p size, or a cylinder of radius size[0] and height size[1].
int BatchedWorlds::add_obstacle(int world, const Vec3& center_m, double yaw_rad, bool box,
                                const Vec3& size, const Vec3& rgb) {
  World& w = world_at(world);
  if (!std::isfinite(yaw_rad)) throw std::invalid_argument("yaw must be finite");
  const int handle = static_cast<int>(w.obstacles.size());
  // Normalised here and again by the world, as the binding hands the simulator's arena in
  // (sim/arena.py), so that both hold the very same bits.
  const Pose pose{center_m, Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ())).normalized()};
  if (box) {
    w.collision->add_box(handle, size, pose, rgb, kGroupStatic);
  } else {
    w.collision->add_cylinder(handle, size[0], size[1], pose, rgb, kGroupStatic);
  }
  w.obstacles.push_back(handle);
  return handle;
}

void BatchedWorlds::clear_obstacles(int world) {
  World& w = world_at(world);
  for (const int handle : w.obstacles) w.collision->remove(handle);
  w.obstacles.clear();
}

void BatchedWorlds::set_pose(int world, int robot, double x_m, double y_m, double yaw_rad) {
  World& w = world_at(world);
  if (robot < 0 || robot >= robots_) {
    throw std::out_of_range("robot index " + std::to_string(robot) + " out of range [0, " +
                            std::to_string(robots_) + ")");
  }
  w.swarm->set_pose(robot, x_m, y_m, yaw_rad);
  w.swarm->set_odometry(robot, x_m, y_m, yaw_rad);
  w.outputs_stale = any_stale_ = true;
}

void BatchedWorlds::reset_world(int world, std::uint64_t seed) {
  World& w = world_at(world);
  w.swarm->reset(seed);
  w.outputs_stale = any_stale_ = true;
}

// Calls apply(b, first row) for each world; when one throws, restore(b, first row) puts back
// the settings of the worlds already changed before the exception goes on.
template <typename Apply, typename Restore>
void BatchedWorlds::for_each_world(Apply apply, Restore restore) {
  int b = 0;
  try {
    for (; b < worlds(); ++b) apply(*worlds_[b].swarm, first_row(b));
  } catch (...) {
    for (int done = 0; done < b; ++done) restore(*worlds_[done].swarm, first_row(done));
    throw;
  }
}

void BatchedWorlds::set_ir_noise(const Eigen::Ref<const RowMatrixXd>& probability,
                                 const Eigen::Ref<const RowMatrixXd>& mean_m,
                                 const Eigen::Ref<const RowMatrixXd>& stddev_m) {
  check_shape(probability, size(), sensor_count_, "probability");
  check_shape(mean_m, size(), sensor_count_, "mean_m");
  check_shape(stddev_m, size(), sensor_count_, "stddev_m");
  const auto set = [this](const auto& p, const auto& m, const auto& s) {
    return [this, &p, &m, &s](EpuckSwarm& swarm, Eigen::Index row) {
      swarm.set_ir_noise(p.middleRows(row, robots_), m.middleRows(row, robots_),
                         s.middleRows(row, robots_));
    };
  };
  for_each_world(set(probability, mean_m, stddev_m),
                 set(noise_.ir_probability, noise_.ir_mean_m, noise_.ir_stddev_m));
  noise_.ir_probability = probability;
  noise_.ir_mean_m = mean_m;
  noise_.ir_stddev_m = stddev_m;
}

void BatchedWorlds::set_imu_noise(const Eigen::Ref<const RowMatrixXd>& accel_stddev,
                                  const Eigen::Ref<const RowMatrixXd>& gyro_stddev) {
  check_shape(accel_stddev, size(), 3, "accel_stddev");
  check_shape(gyro_stddev, size(), 3, "gyro_stddev");
  const auto set = [this](const auto& a, const auto& g) {
    return [this, &a, &g](EpuckSwarm& swarm, Eigen::Index row) {
      swarm.set_imu_noise(a.middleRows(row, robots_), g.middleRows(row, robots_));
    };
  };
  for_each_world(set(accel_stddev, gyro_stddev), set(noise_.accel_stddev, noise_.gyro_stddev));
  noise_.accel_stddev = accel_stddev;
  noise_.gyro_stddev = gyro_stddev;
}

void BatchedWorlds::set_imu_bias(const Eigen::Ref<const RowMatrixXd>& accel_bias,
                                 const Eigen::Ref<const RowMatrixXd>& gyro_bias) {
  check_shape(accel_bias, size(), 3, "accel_bias");
  check_shape(gyro_bias, size(), 3, "gyro_bias");
  const auto set = [this](const auto& a, const auto& g) {
    return [this, &a, &g](EpuckSwarm& swarm, Eigen::Index row) {
      swarm.set_imu_bias(a.middleRows(row, robots_), g.middleRows(row, robots_));
    };
  };
  for_each_world(set(accel_bias, gyro_bias), set(noise_.accel_bias, noise_.gyro_bias));
  noise_.accel_bias = accel_bias;
  noise_.gyro_bias = gyro_bias;
}

void BatchedWorlds::set_slip_noise(const Eigen::Ref<const VectorXd>& stddev) {
  check_length(stddev.size(), size(), "stddev");
  const auto set = [this](const auto& s) {
    return [this, &s](EpuckSwarm& swarm, Eigen::Index row) {
      swarm.set_slip_noise(s.segment(row, robots_));
    };
  };
  for_each_world(set(stddev), set(noise_.slip_stddev));
  noise_.slip_stddev = stddev;
}

void BatchedWorlds::step(double dt_s, const Eigen::Ref<const RowMatrixXd>& wheel_cmd_rad_s) {
  if (!(dt_s > 0.0 && dt_s <= kMaxStep_s)) {
    throw std::invalid_argument("dt_s must be in (0, " + std::to_string(kMaxStep_s) + "]");
  }
  check_shape(wheel_cmd_rad_s, size(), 2, "wheel_cmd");
  if (!wheel_cmd_rad_s.allFinite()) throw std::invalid_argument("wheel_cmd must be finite");
  for (int b = 0; b < worlds(); ++b) {
    worlds_[b].swarm->step(dt_s, wheel_cmd_rad_s.middleRows(first_row(b), robots_));
    write_rows(b);
  }
}

// Copies world b's state into its rows of the buffers.
void BatchedWorlds::write_rows(int world) const {
  const Eigen::Index row = first_row(world);
  const SwarmOutputRows rows{poses_.row(row).data(),        velocities_.row(row).data(),
                             wheel_speeds_.row(row).data(), odometry_.row(row).data(),
                             ranges_.row(row).data(),       ranges_clean_.row(row).data(),
                             accel_.row(row).data(),        gyro_.row(row).data(),
                             in_contact_.data() + row};
  worlds_[world].swarm->write_outputs(rows);
  worlds_[world].outputs_stale = false;
}

void BatchedWorlds::refresh() const {
  if (!any_stale_) return;
  for (int b = 0; b < worlds(); ++b) {
    if (worlds_[b].outputs_stale) write_rows(b);
  }
  any_stale_ = false;
}

const RowMatrixXd& BatchedWorlds::poses() const { return refresh(), poses_; }
const RowMatrixXd& BatchedWorlds::velocities() const { return refresh(), velocities_; }
const RowMatrixXd& BatchedWorlds::wheel_speeds() const { return refresh(), wheel_speeds_; }
const RowMatrixXd& BatchedWorlds::odometry() const { return refresh(), odometry_; }
const RowMatrixXd& BatchedWorlds::ranges() const { return refresh(), ranges_; }
const RowMatrixXd& BatchedWorlds::ranges_clean() const { return refresh(), ranges_clean_; }
const RowMatrixXd& BatchedWorlds::accel() const { return refresh(), accel_; }
const RowMatrixXd& BatchedWorlds::gyro() const { return refresh(), gyro_; }
const VectorXb& BatchedWorlds::in_contact() const { return refresh(), in_contact_; }

Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> BatchedWorlds::frames() const {
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> out(worlds());
  for (int b = 0; b < worlds(); ++b) out[b] = worlds_[b].swarm->frame();
  return out;
}

const CollisionWorld& BatchedWorlds::collision_world(int world) const {
  return *world_at(world).collision;
}

const EpuckSwarm& BatchedWorlds::swarm(int world) const { return *world_at(world).swarm; }

}  // namespace evc
