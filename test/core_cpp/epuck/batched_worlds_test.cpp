// BatchedWorlds' determinism, in C++ alone: two batches built the same way with the same seeds
// and stepped with the same commands hold bit-identical output buffers; a different seed in one
// world changes that world's noise and nothing else; resetting a world repeats its first run.
// Three worlds of four e-pucks in a walled square with a cylinder, every noise source on.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "epuck_vrep_compat/epuck/batched_worlds.hpp"
#include "epuck_vrep_compat/random/rng.hpp"

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
  batch->set_ir_noise(RowMatrixXd::Constant(kRows, 8, 0.5), RowMatrixXd::Constant(kRows, 8, 0.002),
                      RowMatrixXd::Constant(kRows, 8, 0.001));
  batch->set_imu_noise(RowMatrixXd::Constant(kRows, 3, 0.05),
                       RowMatrixXd::Constant(kRows, 3, 0.01));
  batch->set_slip_noise(evc::VectorXd::Constant(kRows, 0.05));
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

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
