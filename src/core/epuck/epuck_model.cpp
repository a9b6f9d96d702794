#include "epuck_vrep_compat/epuck/epuck_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace evc {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

void check_positive(double value, const char* name) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(std::string(name) + " must be finite and > 0");
  }
}

}  // namespace

std::vector<ConeSensor> default_epuck_sensors() {
  struct Mount {
    double x_m, y_m, yaw_deg;
  };
  static const Mount kMounts[] = {
      {0.035, -0.010, -17.2}, {0.025, -0.025, -45.9}, {0.000, -0.030, -90.0},
      {-0.035, -0.020, -151.5}, {-0.035, 0.020, 151.2}, {0.000, 0.030, 90.0},
      {0.025, 0.025, 45.8},   {0.035, 0.010, 17.1},
  };
  std::vector<ConeSensor> sensors;
  for (const Mount& mount : kMounts) {
    ConeSensor sensor;
    sensor.position_m = Vec3(mount.x_m, mount.y_m, 0.034);
    sensor.yaw_rad = mount.yaw_deg * kDegToRad;
    sensors.push_back(sensor);
  }
  return sensors;
}

void validate_epuck_model(const EpuckModel& model) {
  check_positive(model.wheel_radius_m, "wheel_radius_m");
  check_positive(model.wheel_separation_m, "wheel_separation_m");
  check_positive(model.body_radius_m, "body_radius_m");
  check_positive(model.body_height_m, "body_height_m");
  check_positive(model.max_wheel_speed_rad_s, "max_wheel_speed_rad_s");
  if (!std::isfinite(model.gravity_m_s2) || model.gravity_m_s2 < 0.0) {
    throw std::invalid_argument("gravity_m_s2 must be finite and >= 0");
  }
  if (model.sensors.empty()) throw std::invalid_argument("sensors must not be empty");
  for (size_t i = 0; i < model.sensors.size(); ++i) {
    try {
      validate_cone_sensor(model.sensors[i]);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument("sensors[" + std::to_string(i) + "]: " + error.what());
    }
  }
}

}  // namespace evc
