// A small world (at most 32 bodies) finds what its robots' cones may see and what they may touch
// by testing every body, without Bullet's broadphase; a larger one asks the broadphase. Both
// must give the same readings bit for bit: the same crowded arena, once alone and once with
// far-away cylinders added (which nothing reaches) to push it past 32 bodies, stepped with the
// same seeds and commands, every noise on, holds the same outputs at every step. The bodies in
// handle order follow adds and removes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "epuck_vrep_compat/epuck/batched_worlds.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"
#include "every_noise.hpp"

namespace {

using evc::BatchedWorlds;
using evc::RowMatrixXd;
using evc::Vec3;

constexpr double kDt_s = 0.05;
constexpr int kRobots = 8;
constexpr double kHalf_m = 0.16;
using evc::kSmallWorld;  // the core's bound (collision_world.hpp)

// A crowded square: the robots bump into each other and walls.

std::unique_ptr<BatchedWorlds> crowded(int far_cylinders) {
  auto batch = std::make_unique<BatchedWorlds>(evc::EpuckModel(), 1, kRobots,
                                               std::vector<std::uint64_t>{77});
  const double offset = kHalf_m + 0.005;
  batch->add_box(0, Vec3(offset, 0, 0.05), Vec3(0.005, kHalf_m, 0.05), 0.3);
  batch->add_box(0, Vec3(-offset, 0, 0.05), Vec3(0.005, kHalf_m, 0.05), 0.0);
  batch->add_box(0, Vec3(0, offset, 0.05), Vec3(kHalf_m, 0.005, 0.05), 0.0);
  batch->add_box(0, Vec3(0, -offset, 0.05), Vec3(kHalf_m, 0.005, 0.05), -0.2);
  batch->add_cylinder(0, Vec3(0.05, 0.06, 0.05), 0.02, 0.1);
  for (int k = 0; k < far_cylinders; ++k) {
    batch->add_cylinder(0, Vec3(50.0 + k, 40.0, 0.05), 0.02, 0.1);
  }
  for (int r = 0; r < kRobots; ++r) {
    batch->set_pose(0, r, -0.12 + 0.075 * (r % 4), -0.08 + 0.12 * (r / 4), 0.7 * r);
  }
  set_every_noise(*batch, kRobots);
  return batch;
}

bool same(const RowMatrixXd& a, const RowMatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(SmallWorld, ReadsAsTheBroadphaseDoes) {
  const auto small = crowded(0);
  const auto large = crowded(30);
  ASSERT_LE(small->collision_world(0).bodies_in_handle_order().size(), kSmallWorld);
  ASSERT_GT(large->collision_world(0).bodies_in_handle_order().size(), kSmallWorld);
  evc::Rng commands(99);
  RowMatrixXd command(kRobots, 2);
  int contacts = 0, detections = 0;
  for (int s = 0; s < 300; ++s) {
    for (Eigen::Index i = 0; i < command.size(); ++i) {
      command.data()[i] = -3.0 + 9.0 * commands.uniform();
    }
    small->step(kDt_s, command);
    large->step(kDt_s, command);
    ASSERT_TRUE(same(small->poses(), large->poses())) << "step " << s;
    ASSERT_TRUE(same(small->ranges(), large->ranges())) << "step " << s;
    ASSERT_TRUE(same(small->ranges_clean(), large->ranges_clean())) << "step " << s;
    ASSERT_TRUE(same(small->accel(), large->accel())) << "step " << s;
    ASSERT_TRUE(small->in_contact() == large->in_contact()) << "step " << s;
    ASSERT_TRUE(small->swarm(0).detected_handles() == large->swarm(0).detected_handles());
    ASSERT_TRUE(same(small->swarm(0).detected_points(), large->swarm(0).detected_points()));
    contacts += static_cast<int>(small->in_contact().count());
    detections += static_cast<int>((small->swarm(0).detected_handles().array() >= 0).count());
  }
  // The run exercised both lists: robots touched things, and cones saw them.
  EXPECT_GT(contacts, 50);
  EXPECT_GT(detections, 500);
}

TEST(SmallWorld, BodiesInHandleOrderFollowAddsAndRemoves) {
  evc::CollisionWorld world;
  const evc::Pose pose{Vec3(0, 0, 0.05), evc::Quat::Identity()};
  for (const int handle : {7, 2, 40, 5}) {
    world.add_cylinder(handle, 0.02, 0.1, pose, Vec3(0.5, 0.5, 0.5));
  }
  world.remove(5);
  world.add_box(3, Vec3(0.1, 0.1, 0.1), pose, Vec3(0.5, 0.5, 0.5));
  // handles() reads the ordered list.
  EXPECT_EQ(world.handles(), (std::vector<int>{2, 3, 7, 40}));
  EXPECT_EQ(world.bodies_in_handle_order().size(), 4u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
