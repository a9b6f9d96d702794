// BatchedWorlds' determinism, in C++ alone: two batches built the same way with the same seeds
// and stepped with the same commands hold bit-identical output buffers; a different seed in one
// world changes that world's noise and nothing else; resetting a world repeats its first run;
// a world's outputs are those of a standalone swarm (its worlds' swarms share their model, rays
// and working lists, which must carry nothing from one world to the next).
// Three worlds of four e-pucks in a walled square with a cylinder, every noise source on.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "epuck_vrep_compat/epuck/batched_worlds.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "every_noise.hpp"

namespace {

using evc::BatchedWorlds;
using evc::RowMatrixXd;
using evc::Vec3;

constexpr double kDt_s = 0.05;
constexpr int kWorlds = 3;
constexpr int kRobots = 4;
constexpr int kRows = kWorlds * kRobots;
constexpr double kHalf_m = 0.25;

void place(BatchedWorlds& batch, int world) {
  for (int r = 0; r < kRobots; ++r) {
    batch.set_pose(world, r, -0.18 + 0.08 * r, -0.1 + 0.07 * world, 0.4 * r + world);
  }
}

/// The arena in every world, the robots placed, every noise on.
std::unique_ptr<BatchedWorlds> noisy_batch(const std::vector<std::uint64_t>& seeds) {
  auto batch = std::make_unique<BatchedWorlds>(evc::EpuckModel(), kWorlds, kRobots, seeds);
  for (int w = 0; w < kWorlds; ++w) {
    const double offset = kHalf_m + 0.005;
    batch->add_box(w, Vec3(offset, 0, 0.05), Vec3(0.005, kHalf_m, 0.05), 0.0);
    batch->add_box(w, Vec3(-offset, 0, 0.05), Vec3(0.005, kHalf_m, 0.05), 0.0);
    batch->add_box(w, Vec3(0, offset, 0.05), Vec3(kHalf_m, 0.005, 0.05), 0.0);
    batch->add_box(w, Vec3(0, -offset, 0.05), Vec3(kHalf_m, 0.005, 0.05), 0.0);
    batch->add_cylinder(w, Vec3(0.1, 0.12, 0.05), 0.03, 0.1);
    place(*batch, w);
  }
  set_every_noise(*batch, kRows);
  return batch;
}

/// Step @p steps times with commands uniform in [-7, 7] rad/s from one seeded stream.
void run(BatchedWorlds& batch, int steps, std::uint64_t command_seed = 1234) {
  evc::Rng commands(command_seed);
  RowMatrixXd command(kRows, 2);
  for (int s = 0; s < steps; ++s) {
    for (Eigen::Index i = 0; i < command.size(); ++i) {
      command.data()[i] = -7.0 + 14.0 * commands.uniform();
    }
    batch.step(kDt_s, command);
  }
}

/// Rows [first, first + count) of @p a and @p b hold the same bytes.
bool same_rows(const RowMatrixXd& a, const RowMatrixXd& b, int first = 0, int count = kRows) {
  return a.cols() == b.cols() &&
         std::memcmp(a.row(first).data(), b.row(first).data(),
                     sizeof(double) * a.cols() * count) == 0;
}

void expect_same(const BatchedWorlds& a, const BatchedWorlds& b, int first = 0,
                 int count = kRows) {
  EXPECT_TRUE(same_rows(a.poses(), b.poses(), first, count)) << "poses";
  EXPECT_TRUE(same_rows(a.velocities(), b.velocities(), first, count)) << "velocities";
  EXPECT_TRUE(same_rows(a.wheel_speeds(), b.wheel_speeds(), first, count)) << "wheel_speeds";
  EXPECT_TRUE(same_rows(a.odometry(), b.odometry(), first, count)) << "odometry";
  EXPECT_TRUE(same_rows(a.ranges(), b.ranges(), first, count)) << "ranges";
  EXPECT_TRUE(same_rows(a.ranges_clean(), b.ranges_clean(), first, count)) << "ranges_clean";
  EXPECT_TRUE(same_rows(a.accel(), b.accel(), first, count)) << "accel";
  EXPECT_TRUE(same_rows(a.gyro(), b.gyro(), first, count)) << "gyro";
  EXPECT_EQ(a.in_contact().segment(first, count), b.in_contact().segment(first, count));
}

TEST(BatchedWorldsDeterminism, SameSeedsAndCommandsGiveBitIdenticalBuffers) {
  auto a = noisy_batch({1, 2, 3});
  auto b = noisy_batch({1, 2, 3});
  const RowMatrixXd start = a->poses();
  run(*a, 500);
  run(*b, 500);
  expect_same(*a, *b);
  EXPECT_EQ(a->frames(), b->frames());
  EXPECT_EQ(a->frames()[2], 500);
  // Not vacuous: the robots moved, bumped into things, and the noise changed readings.
  EXPECT_FALSE(same_rows(start, a->poses()));
  EXPECT_FALSE(same_rows(a->ranges(), a->ranges_clean()));
}

TEST(BatchedWorldsDeterminism, AnotherSeedChangesOnlyItsWorld) {
  auto a = noisy_batch({1, 2, 3});
  auto b = noisy_batch({1, 9, 3});
  run(*a, 100);
  run(*b, 100);
  expect_same(*a, *b, 0, kRobots);
  expect_same(*a, *b, 2 * kRobots, kRobots);
  EXPECT_FALSE(same_rows(a->ranges(), b->ranges(), kRobots, kRobots));
  EXPECT_FALSE(same_rows(a->accel(), b->accel(), kRobots, kRobots));
}

TEST(BatchedWorldsDeterminism, AResetWorldRepeatsItsFirstRun) {
  auto fresh = noisy_batch({1, 2, 3});
  auto reused = noisy_batch({5, 6, 7});
  run(*reused, 300, 99);
  for (int w = 0; w < kWorlds; ++w) {
    reused->reset_world(w, static_cast<std::uint64_t>(w + 1));
    place(*reused, w);
  }
  EXPECT_EQ(reused->frames().sum(), 0);
  run(*fresh, 200);
  run(*reused, 200);
  expect_same(*fresh, *reused);
}

TEST(BatchedWorldsDeterminism, AWorldIsAStandaloneSwarm) {
  auto batch = noisy_batch({1, 2, 3});
  const int world = 1;
  // The same world built alone, as BatchedWorlds builds it: obstacles under handles 0, 1, ...
  // (their orientations normalised), robots added on the start grid, then placed.
  evc::CollisionWorld alone_world;
  const double offset = kHalf_m + 0.005;
  const auto pose = [](const Vec3& centre) {
    return evc::Pose{centre, evc::Quat(Eigen::AngleAxisd(0.0, Vec3::UnitZ())).normalized()};
  };
  const evc::Vec3 grey = evc::kObstacleRgb;
  alone_world.add_box(0, Vec3(0.005, kHalf_m, 0.05), pose(Vec3(offset, 0, 0.05)), grey);
  alone_world.add_box(1, Vec3(0.005, kHalf_m, 0.05), pose(Vec3(-offset, 0, 0.05)), grey);
  alone_world.add_box(2, Vec3(kHalf_m, 0.005, 0.05), pose(Vec3(0, offset, 0.05)), grey);
  alone_world.add_box(3, Vec3(kHalf_m, 0.005, 0.05), pose(Vec3(0, -offset, 0.05)), grey);
  alone_world.add_cylinder(4, 0.03, 0.1, pose(Vec3(0.1, 0.12, 0.05)), grey);
  evc::EpuckSwarm alone(alone_world, evc::EpuckModel(), 2);
  for (int r = 0; r < kRobots; ++r) {
    alone.add_robot(BatchedWorlds::kRobotHandleBase + r, 0.1 * (r % 2) - 0.05,
                    0.1 * (r / 2) - 0.05, 0.0);
    const double x = -0.18 + 0.08 * r, y = -0.1 + 0.07 * world, yaw = 0.4 * r + world;
    alone.set_pose(r, x, y, yaw);
    alone.set_odometry(r, x, y, yaw);
  }
  set_every_noise(alone, kRobots);
  evc::Rng commands(4321);
  RowMatrixXd command(kRows, 2);
  for (int s = 0; s < 150; ++s) {
    for (Eigen::Index i = 0; i < command.size(); ++i) {
      command.data()[i] = -7.0 + 14.0 * commands.uniform();
    }
    batch->step(kDt_s, command);
    alone.step(kDt_s, command.middleRows(world * kRobots, kRobots));
  }
  const evc::EpuckSwarm& in_batch = batch->swarm(world);
  EXPECT_TRUE(same_rows(in_batch.poses(), alone.poses(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.odometry(), alone.odometry(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.ranges(), alone.ranges(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.ranges_clean(), alone.ranges_clean(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.accel(), alone.accel(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.gyro(), alone.gyro(), 0, kRobots));
  EXPECT_TRUE(same_rows(in_batch.detected_points(), alone.detected_points(), 0, kRobots * 8));
  EXPECT_EQ(in_batch.detected_handles(), alone.detected_handles());
  EXPECT_EQ(in_batch.in_contact(), alone.in_contact());
  // Something was seen and touched, so the comparison covered the cones and the contacts.
  EXPECT_TRUE((alone.detected_handles().array() >= 0).any());
  // And the batch's buffers hold the same (write_outputs).
  EXPECT_EQ(std::memcmp(batch->ranges().row(world * kRobots).data(), alone.ranges().data(),
                        sizeof(double) * 8 * kRobots), 0);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
