// Internal: the one check of a pose handed to the core (an object's, a sensor's).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "epuck_vrep_compat/world/collision_world.hpp"
#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

// Returns the pose with its quaternion normalised; rejects what cannot be normalised and
// positions that are not finite or beyond ±kWorldLimit_m (std::invalid_argument).
inline Pose checked_pose(const Pose& pose) {
  if (!(pose.position_m.array().abs() <= kWorldLimit_m).all()) {
    throw std::invalid_argument("position must be finite and within ±1e6 m");
  }
  const double norm = pose.orientation.coeffs().norm();
  if (!std::isfinite(norm) || norm < 1e-9) {
    throw std::invalid_argument("quaternion must be finite and non-zero");
  }
  return Pose{pose.position_m, Quat(pose.orientation.coeffs() / norm)};
}

// checked_pose of poses[i], its messages prefixed with "<name>[i]: ".
inline Pose checked_pose_at(const std::vector<Pose>& poses, std::size_t i, const char* name) {
  try {
    return checked_pose(poses[i]);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string(name) + "[" + std::to_string(i) + "]: " +
                                error.what());
  }
}

}  // namespace evc
