/// @file
/// A pinhole camera that ray-casts a CollisionWorld, one ray per pixel.
///
/// Frames: the camera body frame is REP 103 (x forward = optical axis, y left, z up). Row 0 is
/// the top of the image and column 0 its left, as in ROS images. With square pixels and
/// f = (H / 2) / tan(vertical_fov / 2) pixels, the pixel (row, col) looks along
///
///     d = (1, -(col + 0.5 - W/2) / f, -(row + 0.5 - H/2) / f)      (camera body frame)
///
/// so the horizontal field of view follows from the aspect ratio.
///
/// Shading: colour = object rgb × (0.35 + 0.65 |n · L|), with n the surface normal and L a fixed
/// light direction (world frame); the background colour where nothing is hit within far_m.
/// Depth: the distance along the optical axis, t d_x / |d|, clamped to [near_m, far_m]; far_m
/// where nothing is hit.
///
/// The image equals one CollisionWorld::ray_cast per pixel (test_camera_speed_equivalence.py
/// checks it pixel for pixel) at a fraction of the cost: per image, the broadphase and bounding
/// spheres keep the objects that can appear, each with the pixel rectangle its projection can
/// cover and a lower bound on its depth; they are drawn nearest bound first into a depth buffer,
/// a pixel testing its exact ray against the object only if no nearer hit covers it already.
/// Measured here, 160 × 120 in a 100-robot arena takes ~0.25 ms (one ray_cast per pixel: ~5 ms).
/// Exact ties between coincident surfaces go to the smaller depth bound, then the lower handle.
/// A camera inside an object sees it at near_m everywhere; on its surface, wherever the closed
/// form counts the touch as a hit. Safe to call from several threads on an unchanging world.
#pragma once

#include <cstdint>
#include <vector>

#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// Intrinsics and clipping of a camera.
struct CameraSpec {
  int width = 160;
  int height = 120;
  double vertical_fov_rad = 0.785398163;
  double near_m = 0.01;
  double far_m = 10.0;
};

/// A rendered frame, row-major, row 0 at the top.
struct CameraImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< height × width × 3
  std::vector<float> depth_m;     ///< height × width
};

/// Renders @p world from @p camera_pose (camera body frame in the world), seeing the groups in
/// @p mask except @p ignore_handle (the robot carrying the camera). Throws
/// std::invalid_argument for a non-finite pose, sizes < 1, fov outside (0, π) or
/// not 0 < near_m < far_m <= kWorldLimit_m.
CameraImage render(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                   int ignore_handle = -1, int mask = kGroupAll);

/// render() into the caller's buffers: @p rgb (height × width × 3 bytes) and @p depth_m
/// (height × width), either of them null when not wanted. What is not asked for is not
/// computed (a depth image alone skips the shading; a colour image alone the depth's clamping),
/// and what is asked for is bit for bit render()'s. Throws as render() does.
void render_into(const CollisionWorld& world, const Pose& camera_pose, const CameraSpec& spec,
                 int ignore_handle, int mask, std::uint8_t* rgb, float* depth_m);

/// Renders the colour image of each of @p camera_poses, image k not seeing
/// @p ignore_handles[k], all with @p spec, into @p rgb_out (poses × height × width × 3 bytes,
/// image after image), on up to @p threads threads (the world must not change meanwhile).
/// Each image is byte-identical to render()'s. Checks every pose, and throws as render() does,
/// before drawing anything.
void render_rgb_batch(const CollisionWorld& world, const std::vector<Pose>& camera_poses,
                      const std::vector<int>& ignore_handles, const CameraSpec& spec, int mask,
                      int threads, std::uint8_t* rgb_out);

}  // namespace evc
