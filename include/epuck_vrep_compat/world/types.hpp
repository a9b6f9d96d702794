/// @file
/// Value types shared by the core's public API: Eigen vectors and row-major matrices, so that a
/// binding can exchange them with numpy without reshaping.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace evc {

/// A 3-vector in metres (or a direction, or an RGB triple in 0..1, as the name says).
using Vec3 = Eigen::Vector3d;
/// A unit quaternion; constructed from (w, x, y, z), exchanged with Python as (x, y, z, w).
using Quat = Eigen::Quaterniond;
/// A dense row-major matrix of doubles: row i is item i (ray, robot), as numpy lays it out.
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// A dense row-major matrix of 32-bit ints (handles).
using RowMatrixXi = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// A column of doubles.
using VectorXd = Eigen::VectorXd;
/// A column of 32-bit ints.
using VectorXi = Eigen::VectorXi;
/// A column of booleans.
using VectorXb = Eigen::Matrix<bool, Eigen::Dynamic, 1>;

/// A rigid pose in the world frame.
struct Pose {
  Vec3 position_m = Vec3::Zero();               ///< origin of the body frame, metres
  Quat orientation = Quat::Identity();          ///< body-to-world rotation
};

}  // namespace evc
