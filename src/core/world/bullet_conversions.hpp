// Internal: conversions between the public Eigen types and Bullet's (both double precision).
#pragma once

#include <LinearMath/btTransform.h>

#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

inline btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }

inline Vec3 to_eigen(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

inline btTransform to_bt(const Pose& pose) {
  const Quat& q = pose.orientation;
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), to_bt(pose.position_m));
}

inline Pose to_pose(const btTransform& transform) {
  const btQuaternion q = transform.getRotation();
  return Pose{to_eigen(transform.getOrigin()), Quat(q.w(), q.x(), q.y(), q.z())};
}

}  // namespace evc
