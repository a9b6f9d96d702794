// Test helper: every noise source of an EpuckSwarm or a BatchedWorlds on, the same for every
// robot (IR: probability 0.5, mean 2 mm, SD 1 mm; IMU SDs 0.05 and 0.01; slip SD 0.05).
#pragma once

#include "epuck_vrep_compat/world/types.hpp"

template <typename Swarm>
void set_every_noise(Swarm& swarm, int rows) {
  using evc::RowMatrixXd;
  swarm.set_ir_noise(RowMatrixXd::Constant(rows, 8, 0.5), RowMatrixXd::Constant(rows, 8, 0.002),
                     RowMatrixXd::Constant(rows, 8, 0.001));
  swarm.set_imu_noise(RowMatrixXd::Constant(rows, 3, 0.05), RowMatrixXd::Constant(rows, 3, 0.01));
  swarm.set_slip_noise(evc::VectorXd::Constant(rows, 0.05));
}
