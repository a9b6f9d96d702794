// The swarm's state as row-per-robot matrices, the layout the binding hands to numpy: each
// output's row is written by one function below, whether into a new matrix or into a caller's
// buffer (write_outputs).
#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"

#include <algorithm>

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
RowMatrixXd EpuckSwarm::per_robot(int columns, Get get) const {
  RowMatrixXd out(size(), columns);
  for (int i = 0; i < size(); ++i) out.row(i) = get(robots_[i]);
  return out;
}

RowMatrixXd EpuckSwarm::sensor_values(const std::vector<double>& readings) const {
  RowMatrixXd out(size(), sensor_count());
  std::copy(readings.begin(), readings.end(), out.data());
  return out;
}

template <typename Get>
RowMatrixXd EpuckSwarm::per_sensor_vector(Get get) const {
  RowMatrixXd out(static_cast<Eigen::Index>(size()) * sensor_count(), 3);
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) {
      out.row(static_cast<Eigen::Index>(i) * sensor_count() + k) =
          get(detections_[static_cast<std::size_t>(i) * sensor_count() + k]).transpose();
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

RowMatrixXd EpuckSwarm::ranges_clean() const { return sensor_values(clean_m_); }

RowMatrixXd EpuckSwarm::ranges() const { return sensor_values(noisy_m_); }

RowMatrixXi EpuckSwarm::detected_handles() const {
  RowMatrixXi out(size(), sensor_count());
  for (int i = 0; i < size(); ++i) {
    for (int k = 0; k < sensor_count(); ++k) {
      out(i, k) = detections_[static_cast<std::size_t>(i) * sensor_count() + k].handle;
    }
  }
  return out;
}

RowMatrixXd EpuckSwarm::detected_points() const {
  return per_sensor_vector([](const Detection& s) { return s.point_m; });
}

RowMatrixXd EpuckSwarm::detected_normals() const {
  return per_sensor_vector([](const Detection& s) { return s.normal; });
}

RowMatrixXd EpuckSwarm::accel() const { return per_robot(3, kAccelRow); }

RowMatrixXd EpuckSwarm::gyro() const { return per_robot(3, kGyroRow); }

VectorXb EpuckSwarm::in_contact() const {
  VectorXb out(size());
  for (int i = 0; i < size(); ++i) out[i] = robots_[i].in_contact;
  return out;
}

void EpuckSwarm::write_outputs(const SwarmOutputRows& out) const {
  // The readings are kept in the outputs' layout: one copy each (Eigen's, inline, rather than
  // a call to memmove for a few hundred bytes).
  const Eigen::Index readings = static_cast<Eigen::Index>(noisy_m_.size());
  Eigen::Map<VectorXd>(out.ranges, readings) = Eigen::Map<const VectorXd>(noisy_m_.data(), readings);
  Eigen::Map<VectorXd>(out.ranges_clean, readings) =
      Eigen::Map<const VectorXd>(clean_m_.data(), readings);
  for (int i = 0; i < size(); ++i) {
    const Robot& r = robots_[i];
    Eigen::Map<Eigen::RowVector3d>(out.poses + 3 * i) = kPoseRow(r);
    Eigen::Map<Eigen::RowVector3d>(out.velocities + 3 * i) = kVelocityRow(r);
    Eigen::Map<Eigen::RowVector2d>(out.wheel_speeds + 2 * i) = kWheelSpeedRow(r);
    Eigen::Map<Eigen::Matrix<double, 1, 5>>(out.odometry + 5 * i) = kOdometryRow(r);
    Eigen::Map<Eigen::RowVector3d>(out.accel + 3 * i) = kAccelRow(r);
    Eigen::Map<Eigen::RowVector3d>(out.gyro + 3 * i) = kGyroRow(r);
    out.in_contact[i] = r.in_contact;
  }
}

VectorXi EpuckSwarm::handles() const {
  VectorXi out(size());
  for (int i = 0; i < size(); ++i) out[i] = robots_[i].handle;
  return out;
}

std::vector<std::uint64_t> EpuckSwarm::stream_ids() const {
  std::vector<std::uint64_t> out;
  out.reserve(robots_.size());
  for (const RobotNoise& noise : noise_) out.push_back(noise.stream);
  return out;
}

}  // namespace evc
