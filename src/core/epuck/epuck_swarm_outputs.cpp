// The swarm's state as row-per-robot matrices, the layout the binding hands to numpy.
#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"

namespace evc {

template <typename Get>
RowMatrixXd EpuckSwarm::per_robot(int columns, Get get) const {
  RowMatrixXd out(size(), columns);
  for (int i = 0; i < size(); ++i) out.row(i) = get(robots_[i]);
  return out;
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

RowMatrixXd EpuckSwarm::poses() const {
  return per_robot(3, [](const Robot& r) {
    return Eigen::RowVector3d(r.pose.x_m, r.pose.y_m, r.pose.yaw_rad);
  });
}

RowMatrixXd EpuckSwarm::velocities() const {
  return per_robot(3, [](const Robot& r) { return r.velocity.transpose(); });
}

RowMatrixXd EpuckSwarm::wheel_speeds() const {
  return per_robot(2, [](const Robot& r) {
    return Eigen::RowVector2d(r.wheel_speed.left, r.wheel_speed.right);
  });
}

RowMatrixXd EpuckSwarm::wheel_angles() const {
  return per_robot(2, [](const Robot& r) {
    return Eigen::RowVector2d(r.wheel_angle.left, r.wheel_angle.right);
  });
}

RowMatrixXd EpuckSwarm::odometry() const {
  return per_robot(5, [](const Robot& r) {
    Eigen::Matrix<double, 1, 5> row;
    row << r.odometry.x_m, r.odometry.y_m, r.odometry.yaw_rad, r.odometry_twist.v_m_s,
        r.odometry_twist.w_rad_s;
    return row;
  });
}

RowMatrixXd EpuckSwarm::ranges_clean() const {
  return per_robot(sensor_count(), [this](const Robot& r) {
    Eigen::RowVectorXd row(sensor_count());
    for (int k = 0; k < sensor_count(); ++k) row[k] = r.sensors[k].clean_m;
    return row;
  });
}

RowMatrixXd EpuckSwarm::ranges() const {
  return per_robot(sensor_count(), [this](const Robot& r) {
    Eigen::RowVectorXd row(sensor_count());
    for (int k = 0; k < sensor_count(); ++k) row[k] = r.sensors[k].noisy_m;
    return row;
  });
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

RowMatrixXd EpuckSwarm::accel() const {
  return per_robot(3, [](const Robot& r) { return r.accel.transpose(); });
}

RowMatrixXd EpuckSwarm::gyro() const {
  return per_robot(3, [](const Robot& r) { return r.gyro.transpose(); });
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
