// LaserScanner in C++ alone: a scan of a wall gives the analytic range on every beam that
// meets it and +inf on the others; an object nearer than range_min reads -inf; the same seed
// gives the same noisy scan, another seed another.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "epuck_vrep_compat/sensors/laser_scanner.hpp"

namespace {

using evc::CollisionWorld;
using evc::LaserScanner;
using evc::LaserSpec;
using evc::Pose;
using evc::Vec3;

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A wall 1 m to the scanner's left: its face is the line y = 1 for -0.5 <= x <= 0.5.
void add_wall(CollisionWorld& world) {
  Pose pose;
  pose.position_m = Vec3(0.0, 1.01, 0.0);
  world.add_box(1, Vec3(0.5, 0.01, 0.5), pose, Vec3(0.5, 0.5, 0.5));
}

TEST(LaserScanner, AWallReadsOneOverTheSineOfEachBeamThatMeetsIt) {
  CollisionWorld world;
  add_wall(world);
  LaserScanner scanner(LaserSpec{});  // the Hokuyo: 682 beams over ±119.5°, 0.02–5.6 m
  const std::vector<float> ranges = scanner.scan(world, Pose{});
  ASSERT_EQ(ranges.size(), 682u);
  int on_wall = 0;
  for (int k = 0; k < scanner.spec().count; ++k) {
    const double angle = scanner.spec().angle_min_rad + k * scanner.spec().angle_increment_rad;
    const double wall_x = std::cos(angle) / std::sin(angle);  // where the beam meets y = 1
    if (angle > 0.0 && std::abs(wall_x) < 0.49) {
      EXPECT_NEAR(ranges[k], 1.0 / std::sin(angle), 1e-6) << "beam " << k;
      ++on_wall;
    } else if (angle <= 0.0 || std::abs(wall_x) > 0.51) {
      EXPECT_EQ(ranges[k], kInf) << "beam " << k;
    }
  }
  EXPECT_GT(on_wall, 100);  // 2 atan(0.49) of 2π/1024 steps: about 150 beams
}

TEST(LaserScanner, AnObjectNearerThanRangeMinReadsMinusInfinity) {
  CollisionWorld world;
  Pose pose;
  pose.position_m = Vec3(0.02, 0.0, 0.0);
  world.add_box(1, Vec3(0.01, 0.5, 0.5), pose, Vec3(0.5, 0.5, 0.5));  // face at x = 0.01
  LaserSpec spec;
  spec.angle_min_rad = -0.1;
  spec.angle_increment_rad = 0.1;
  spec.count = 3;
  spec.range_min_m = 0.05;
  for (float range : LaserScanner(spec).scan(world, Pose{})) EXPECT_EQ(range, -kInf);
}

TEST(LaserScanner, TheSameSeedGivesTheSameNoisyScanAndAnotherSeedAnother) {
  CollisionWorld world;
  add_wall(world);
  LaserSpec spec;
  spec.sigma_min_m = 0.01;
  LaserScanner a(spec, 5), b(spec, 5), c(spec, 6);
  const std::vector<float> first = a.scan(world, Pose{});
  EXPECT_EQ(first, b.scan(world, Pose{}));
  EXPECT_NE(first, c.scan(world, Pose{}));
  EXPECT_NE(first, LaserScanner(LaserSpec{}).scan(world, Pose{}));  // the noise is on
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
