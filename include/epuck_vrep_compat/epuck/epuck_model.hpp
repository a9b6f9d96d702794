/// @file
/// The e-puck's geometry and limits, with the defaults of V-REP's e-puck model.
#pragma once

#include <vector>

#include "epuck_vrep_compat/epuck/cone_sensor.hpp"

namespace evc {

/// The eight proximity sensors of the e-puck (prox0..prox7, clockwise from front-right):
/// mounts at z = 0.034 m, headings -17.2°, -45.9°, -90°, -151.5°, 151.2°, 90°, 45.8°, 17.1°.
std::vector<ConeSensor> default_epuck_sensors();

/// Geometry and limits shared by every robot of a swarm (a plain value type).
struct EpuckModel {
  double wheel_radius_m = 0.02;
  double wheel_separation_m = 0.053;
  double body_radius_m = 0.037;           ///< the body is a cylinder standing on the ground
  double body_height_m = 0.045;
  double max_wheel_speed_rad_s = 6.283185307;  ///< 1000 motor steps/s
  std::vector<ConeSensor> sensors = default_epuck_sensors();
  double gravity_m_s2 = 9.81;
};

/// Throws std::invalid_argument unless every size is finite and > 0, gravity is finite and
/// >= 0, there is at least one sensor and every sensor passes validate_cone_sensor.
void validate_epuck_model(const EpuckModel& model);

}  // namespace evc
