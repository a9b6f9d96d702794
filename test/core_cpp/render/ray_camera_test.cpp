// render() in C++ alone: a camera facing a coloured wall sees that colour, shaded alike over
// the flat face, on exactly the pixels the pinhole model predicts, at the wall's depth; the
// rest is the background at far_m; turned away, it sees only the background.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "epuck_vrep_compat/render/ray_camera.hpp"

namespace {

using evc::CameraImage;
using evc::CameraSpec;
using evc::CollisionWorld;
using evc::Pose;
using evc::Vec3;

using Rgb = std::array<int, 3>;

/// 160 × 120, 60° vertical: f = 60 / tan(30°) = 103.9 px.
CameraSpec spec() {
  CameraSpec camera;
  camera.width = 160;
  camera.height = 120;
  camera.vertical_fov_rad = M_PI / 3.0;
  camera.near_m = 0.01;
  camera.far_m = 5.0;
  return camera;
}

Pose camera_pose(double yaw_rad) {
  Pose pose;
  pose.position_m = Vec3(0.0, 0.0, 0.25);
  pose.orientation = evc::Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  return pose;
}

/// A 0.5 m square wall of colour (1, 0.5, 0.25) facing the camera 1 m ahead, on its axis; its
/// ±0.25 m span ±0.25 f = ±25.98 px about the image centre: rows 34..85, columns 54..105.
void add_wall(CollisionWorld& world) {
  Pose pose;
  pose.position_m = Vec3(1.005, 0.0, 0.25);
  world.add_box(1, Vec3(0.005, 0.25, 0.25), pose, Vec3(1.0, 0.5, 0.25));
  world.set_background(Vec3(0.0, 0.0, 1.0));
}

bool on_wall(int row, int col) { return row >= 34 && row <= 85 && col >= 54 && col <= 105; }

Rgb pixel(const CameraImage& image, int row, int col) {
  const std::size_t at = 3 * (static_cast<std::size_t>(row) * image.width + col);
  return {image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]};
}

TEST(RayCamera, AWallFacingTheCameraIsSeenInItsColourAtItsDepth) {
  CollisionWorld world;
  add_wall(world);
  const CameraImage image = evc::render(world, camera_pose(0.0), spec());
  ASSERT_EQ(image.rgb.size(), 160u * 120u * 3u);
  const Rgb face = pixel(image, 60, 80);
  // The wall's colour times one shade in [0.35, 1] (ambient + diffuse), rounded per channel.
  EXPECT_GE(face[0], 89);
  EXPECT_LE(std::abs(2 * face[1] - face[0]), 2);
  EXPECT_LE(std::abs(4 * face[2] - face[0]), 4);
  for (int row = 0; row < image.height; ++row) {
    for (int col = 0; col < image.width; ++col) {
      const float depth = image.depth_m[static_cast<std::size_t>(row) * image.width + col];
      if (on_wall(row, col)) {
        ASSERT_EQ(pixel(image, row, col), face) << row << ", " << col;
        ASSERT_NEAR(depth, 1.0, 1e-6) << row << ", " << col;  // along the axis, not the ray
      } else {
        ASSERT_EQ(pixel(image, row, col), (Rgb{0, 0, 255})) << row << ", " << col;
        ASSERT_EQ(depth, 5.0f) << row << ", " << col;
      }
    }
  }
}

TEST(RayCamera, TurnedAwayItSeesOnlyTheBackground) {
  CollisionWorld world;
  add_wall(world);
  const CameraImage image = evc::render(world, camera_pose(M_PI), spec());
  for (int row = 0; row < image.height; ++row) {
    for (int col = 0; col < image.width; ++col) {
      ASSERT_EQ(pixel(image, row, col), (Rgb{0, 0, 255})) << row << ", " << col;
    }
  }
}

TEST(RayCamera, RenderIntoGivesWhatIsAskedForAsRenderDoes) {
  CollisionWorld world;
  add_wall(world);
  const CameraImage image = evc::render(world, camera_pose(0.3), spec());
  std::vector<std::uint8_t> rgb(image.rgb.size(), 7);
  std::vector<float> depth(image.depth_m.size(), -1.0f);
  evc::render_into(world, camera_pose(0.3), spec(), -1, evc::kGroupAll, nullptr, depth.data());
  EXPECT_EQ(depth, image.depth_m);
  evc::render_into(world, camera_pose(0.3), spec(), -1, evc::kGroupAll, rgb.data(), nullptr);
  EXPECT_EQ(rgb, image.rgb);
  CameraSpec bad = spec();
  bad.width = 0;
  EXPECT_THROW(evc::render_into(world, camera_pose(0.0), bad, -1, evc::kGroupAll, nullptr,
                                nullptr),
               std::invalid_argument);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
