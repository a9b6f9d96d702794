// The swarm's state as row-per-robot matrices, the layout the binding hands to numpy: each
// output's row is written by one function below, whether into a new matrix or into a caller's
// buffer (write_outputs).
#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"
#include "epuck/shape_checks.hpp"

namespace evc {
namespace {

// One robot's row of each output (generic: the robot type is the swarm's private one).
const auto kPoseRow = [](const auto& r) {
  return Eigen::RowVector3d(r.pose.x_m, r.pose.y_m, r.pose.yaw_rad);
};
const auto kVelocityRow = [](const auto& r) { return r.velocity.transpose(); };
const auto kWheelSpeedRow = [](const auto& r) {
  return Eigen::RowVector2d(r.wheel_speed.left, r.wheel_speed.right);
};
const auto kOdometryRow = [](const auto& r) {
  Eigen::Matrix<double, 1, 5> row;
  row << r.odometry.x_m, r.odometry.y_m, r.odometry.yaw_rad, r.odometry_twist.v_m_s,
      r.odometry_twist.w_rad_s;
  return row;
};
const auto kAccelRow = [](const auto& r) { return r.accel.transpose(); };
const auto kGyroRow = [](const auto& r) { return r.gyro.transpose(); };

}  // namespace

template <typename Get>
void EpuckSwarm::fill_rows(Eigen::Ref<RowMatrixXd> out, Get get) const {
  for (int i = 0; i < size(); ++i) out.row(i) = get(robots_[i]);
}

template <typename Get>
RowMatrixXd EpuckSwarm::per_robot(int columns, Get get) const {
  RowMatrixXd out(size(), columns);
  fill_rows(out, get);
  return out;
}

void EpuckSwarm::fill_ranges(Eigen::Ref<RowMatrixXd> out, double SensorOutput::*reading) const {
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) out(i, k) = robots_[i].sensors[k].*reading;
  }
}

template <typename Get>
RowMatrixXd EpuckSwarm::per_sensor_vector(Get get) const {
  RowMatrixXd out(static_cast<Eigen::Index>(size()) * sensor_count(), 3);
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) {
      out.row(static_cast<Eigen::Index>(i) * sensor_count() + k) =
          get(robots_[i].sensors[k]).transpose();
    }
  }
  return out;
}

RowMatrixXd EpuckSwarm::poses() const { return per_robot(3, kPoseRow); }

RowMatrixXd EpuckSwarm::velocities() const { return per_robot(3, kVelocityRow); }

RowMatrixXd EpuckSwarm::wheel_speeds() const { return per_robot(2, kWheelSpeedRow); }

RowMatrixXd EpuckSwarm::wheel_angles() const {
  return per_robot(2, [](const Robot& r) {
    return Eigen::RowVector2d(r.wheel_angle.left, r.wheel_angle.right);
  });
}

RowMatrixXd EpuckSwarm::odometry() const { return per_robot(5, kOdometryRow); }

RowMatrixXd EpuckSwarm::ranges_clean() const {
  RowMatrixXd out(size(), sensor_count());
  fill_ranges(out, &SensorOutput::clean_m);
  return out;
}

RowMatrixXd EpuckSwarm::ranges() const {
  RowMatrixXd out(size(), sensor_count());
  fill_ranges(out, &SensorOutput::noisy_m);
  return out;
}

RowMatrixXi EpuckSwarm::detected_handles() const {
  RowMatrixXi out(size(), sensor_count());
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) out(i, k) = robots_[i].sensors[k].handle;
  }
  return out;
}

RowMatrixXd EpuckSwarm::detected_points() const {
  return per_sensor_vector([](const SensorOutput& s) { return s.point_m; });
}

RowMatrixXd EpuckSwarm::detected_normals() const {
  return per_sensor_vector([](const SensorOutput& s) { return s.normal; });
}

RowMatrixXd EpuckSwarm::accel() const { return per_robot(3, kAccelRow); }

RowMatrixXd EpuckSwarm::gyro() const { return per_robot(3, kGyroRow); }

VectorXb EpuckSwarm::in_contact() const {
  VectorXb out(size());
  for (int i = 0; i < size(); ++i) out[i] = robots_[i].in_contact;
  return out;
}

void EpuckSwarm::write_outputs(SwarmOutputRows& out) const {
  const Eigen::Index n = size();
  check_shape(out.poses, n, 3, "poses");
  check_shape(out.velocities, n, 3, "velocities");
  check_shape(out.wheel_speeds, n, 2, "wheel_speeds");
  check_shape(out.odometry, n, 5, "odometry");
  check_shape(out.ranges, n, sensor_count(), "ranges");
  check_shape(out.ranges_clean, n, sensor_count(), "ranges_clean");
  check_shape(out.accel, n, 3, "accel");
  check_shape(out.gyro, n, 3, "gyro");
  check_length(out.in_contact.size(), n, "in_contact");
  fill_rows(out.poses, kPoseRow);
  fill_rows(out.velocities, kVelocityRow);
  fill_rows(out.wheel_speeds, kWheelSpeedRow);
  fill_rows(out.odometry, kOdometryRow);
  fill_ranges(out.ranges, &SensorOutput::noisy_m);
  fill_ranges(out.ranges_clean, &SensorOutput::clean_m);
  fill_rows(out.accel, kAccelRow);
  fill_rows(out.gyro, kGyroRow);
  for (int i = 0; i < size(); ++i) out.in_contact[i] = robots_[i].in_contact;
}

VectorXi EpuckSwarm::handles() const {
  VectorXi out(size());
  for (int i = 0; i < size(); ++i) out[i] = robots_[i].handle;
  return out;
}

std::vector<std::uint64_t> EpuckSwarm::stream_ids() const {
  std::vector<std::uint64_t> out;
  out.reserve(robots_.size());
  for (const Robot& robot : robots_) out.push_back(robot.stream);
  return out;
}

}  // namespace evc
