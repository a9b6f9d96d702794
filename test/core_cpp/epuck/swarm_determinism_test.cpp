// EpuckSwarm's determinism, in C++ alone: two swarms built the same way with the same seed and
// stepped with the same commands hold bit-identical state arrays; another seed gives other
// noise; reseeding restarts every stream. Five robots in a small walled arena with every noise
// source on, so contacts, cones, the IMU and slip all take part.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "epuck_vrep_compat/epuck/epuck_swarm.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"
#include "every_noise.hpp"

namespace {

using evc::CollisionWorld;
using evc::EpuckModel;
using evc::EpuckSwarm;
using evc::RowMatrixXd;
using evc::RowMatrixXi;

constexpr double kDt_s = 0.05;
constexpr int kRobots = 5;
constexpr double kArenaHalf_m = 0.25;
constexpr std::uint64_t kCommandSeed = 1234;

/// Five e-pucks 3 cm apart in a walled square, IR, IMU and slip noise on.
class NoisyArena {
 public:
  explicit NoisyArena(std::uint64_t seed) : swarm_(world_, EpuckModel(), seed) {
    const double thickness = 0.005;
    const double offset = kArenaHalf_m + thickness;
    const evc::Vec3 grey(0.5, 0.5, 0.5);
    const evc::Vec3 along_y(thickness, kArenaHalf_m, 0.05);
    const evc::Vec3 along_x(kArenaHalf_m, thickness, 0.05);
    world_.add_box(1, along_y, wall_at(offset, 0.0), grey);
    world_.add_box(2, along_y, wall_at(-offset, 0.0), grey);
    world_.add_box(3, along_x, wall_at(0.0, offset), grey);
    world_.add_box(4, along_x, wall_at(0.0, -offset), grey);
    for (int i = 0; i < kRobots; ++i) {
      swarm_.add_robot(100 + i, -0.2 + 0.1 * i, (i % 2 ? -0.02 : 0.02), 0.7 * i);
    }
    set_every_noise(swarm_, kRobots);
  }

  /// @p steps steps with wheel commands uniform in [-7, 7] rad/s from one seeded stream, the
  /// same for every arena.
  void run(int steps) {
    evc::Rng commands(kCommandSeed);
    RowMatrixXd command(kRobots, 2);
    for (int s = 0; s < steps; ++s) {
      for (Eigen::Index i = 0; i < command.size(); ++i) {
        command.data()[i] = -7.0 + 14.0 * commands.uniform();
      }
      swarm_.step(kDt_s, command);
    }
  }

  EpuckSwarm& swarm() { return swarm_; }

 private:
  static evc::Pose wall_at(double x_m, double y_m) {
    evc::Pose pose;
    pose.position_m = evc::Vec3(x_m, y_m, 0.05);
    return pose;
  }

  CollisionWorld world_;  // before swarm_: the swarm holds it
  EpuckSwarm swarm_;
};

/// Every state array a swarm offers, by name.
std::vector<std::pair<std::string, RowMatrixXd>> state_arrays(const EpuckSwarm& swarm) {
  return {{"poses", swarm.poses()},
          {"velocities", swarm.velocities()},
          {"wheel_speeds", swarm.wheel_speeds()},
          {"wheel_angles", swarm.wheel_angles()},
          {"odometry", swarm.odometry()},
          {"ranges_clean", swarm.ranges_clean()},
          {"ranges", swarm.ranges()},
          {"detected_points", swarm.detected_points()},
          {"detected_normals", swarm.detected_normals()},
          {"accel", swarm.accel()},
          {"gyro", swarm.gyro()}};
}

/// Same shape and the same bytes (so -0.0 and 0.0, or two NaNs, are told apart as they are).
template <typename Matrix>
bool bit_identical(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(typename Matrix::Scalar) * a.size()) == 0;
}

void expect_bit_identical(const EpuckSwarm& a, const EpuckSwarm& b) {
  const auto first = state_arrays(a);
  const auto second = state_arrays(b);
  for (std::size_t k = 0; k < first.size(); ++k) {
    EXPECT_TRUE(bit_identical(first[k].second, second[k].second)) << first[k].first;
  }
  EXPECT_TRUE(bit_identical(a.detected_handles(), b.detected_handles())) << "detected_handles";
  EXPECT_EQ(a.frame(), b.frame());
}

TEST(SwarmDeterminism, SameSeedAndCommandsGiveBitIdenticalStateAfter1000Steps) {
  NoisyArena a(7), b(7);
  const RowMatrixXd start = a.swarm().poses();
  a.run(1000);
  b.run(1000);
  expect_bit_identical(a.swarm(), b.swarm());
  EXPECT_EQ(a.swarm().frame(), 1000);
  // Not vacuous: the robots moved, and the noise changed readings.
  EXPECT_FALSE(bit_identical(start, a.swarm().poses()));
  EXPECT_FALSE(bit_identical(a.swarm().ranges(), a.swarm().ranges_clean()));
}

TEST(SwarmDeterminism, ADifferentSeedGivesDifferentNoise) {
  NoisyArena a(7), b(8);
  a.run(50);
  b.run(50);
  EXPECT_FALSE(bit_identical(a.swarm().ranges(), b.swarm().ranges()));
  EXPECT_FALSE(bit_identical(a.swarm().accel(), b.swarm().accel()));
  EXPECT_FALSE(bit_identical(a.swarm().gyro(), b.swarm().gyro()));
  EXPECT_FALSE(bit_identical(a.swarm().wheel_speeds(), b.swarm().wheel_speeds()));
}

TEST(SwarmDeterminism, ReseedingRestartsEveryStream) {
  NoisyArena a(7), b(99);
  b.swarm().reseed(7);
  a.run(200);
  b.run(200);
  expect_bit_identical(a.swarm(), b.swarm());
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
