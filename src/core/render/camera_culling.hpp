// Internal: the per-image set-up of the ray-cast camera (ray_camera.cpp): the camera's rays as
// per-row and per-column constants, and the few objects that can appear in the image, each with
// the rectangle of pixels it can cover and a lower bound on its depth.
//
// Rays are left unnormalised: pixel (row, col) looks along the camera-frame vector
// (1, -col_slope[col], -row_slope[row]), so the ray parameter of a hit is its depth along the
// optical axis, and "within far_m" is "parameter <= far_m".
#pragma once

#include <vector>

#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btVector3.h>

#include "epuck_vrep_compat/render/ray_camera.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"
#include "world/primitive_ray.hpp"

namespace evc {

// Per-image constants of a validated pinhole camera.
struct CameraRays {
  btVector3 position_m;
  btMatrix3x3 rotation;               // camera frame to world frame
  double focal_px = 1.0;              // f = (H / 2) / tan(vertical_fov / 2)
  std::vector<double> col_slope;      // (col + 0.5 - W/2) / f
  std::vector<double> row_slope;      // (row + 0.5 - H/2) / f
  double max_ray_length = 1.0;        // largest |(1, -col_slope, -row_slope)| over the pixels
};

CameraRays camera_rays(const Pose& camera_pose, const CameraSpec& spec);

// An object that may appear in the image. Everything is in the object's own frame, where
// primitive_ray works: the ray of pixel (row, col) is
//     origin + s (forward - col_slope[col] left - row_slope[row] up),  s = depth (m).
struct CameraTarget {
  const Primitive* primitive = nullptr;
  int handle = -1;
  Vec3 rgb = Vec3::Zero();
  btMatrix3x3 basis;                  // object frame to world frame
  btVector3 origin;                   // the camera position
  btVector3 forward, left, up;        // the camera's axes
  enum class Camera { kOutside, kOnSurface, kInside };
  Camera camera = Camera::kOutside;   // where the camera is, relative to the object
  double min_depth_m = 0.0;           // no pixel sees the object nearer than this
  int row_begin = 0, row_end = 0;     // the only pixels whose rays can meet the object:
  int col_begin = 0, col_end = 0;     // rows [row_begin, row_end) × cols [col_begin, col_end)
};

// The objects in @p mask, other than @p ignore_handle, that some pixel ray can meet within
// spec.far_m, nearest first (by min_depth_m, then handle, so the order is deterministic).
// Conservative: it may keep an object no ray meets, never drops one that a ray does meet.
std::vector<CameraTarget> camera_targets(const CollisionWorld& world, const CameraRays& rays,
                                         const CameraSpec& spec, int ignore_handle, int mask);

}  // namespace evc
