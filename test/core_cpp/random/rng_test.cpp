// Rng and derive_seed, the core's only randomness, in C++ alone: the same seed gives the same
// stream, different seeds (and different robots or streams of one seed) give different ones,
// and uniforms stay in (0, 1].
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "epuck_vrep_compat/random/rng.hpp"

namespace {

using evc::Rng;

std::vector<std::uint64_t> stream(std::uint64_t seed, int count) {
  Rng rng(seed);
  std::vector<std::uint64_t> out;
  for (int i = 0; i < count; ++i) out.push_back(rng.next_u64());
  return out;
}

TEST(Rng, TheSameSeedGivesTheSameStream) {
  EXPECT_EQ(stream(123, 1000), stream(123, 1000));
  Rng a(123), b(123);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.normal(), b.normal());
  EXPECT_EQ(a.state_digest(), b.state_digest());
}

TEST(Rng, DifferentSeedsGiveDifferentStreams) {
  const std::vector<std::uint64_t> zero = stream(0, 1000);
  for (std::uint64_t seed : {1, 2, 3}) {
    const std::vector<std::uint64_t> other = stream(seed, 1000);
    int equal = 0;
    for (int i = 0; i < 1000; ++i) equal += zero[i] == other[i];
    EXPECT_EQ(equal, 0) << "seed " << seed;
  }
  EXPECT_NE(Rng(1).state_digest(), Rng(2).state_digest());
}

TEST(Rng, NeighbouringRobotsAndStreamsGetDistinctSeeds) {
  std::set<std::uint64_t> seeds;
  for (std::uint64_t seed : {0, 1}) {
    for (std::uint64_t robot = 0; robot < 10; ++robot) {
      for (std::uint64_t stream_id = 0; stream_id < 5; ++stream_id) {
        seeds.insert(evc::derive_seed(seed, robot, stream_id));
      }
    }
  }
  EXPECT_EQ(seeds.size(), 2u * 10u * 5u);
  EXPECT_EQ(evc::derive_seed(7, 3, 2), evc::derive_seed(7, 3, 2));
}

TEST(Rng, UniformsAreInTheHalfOpenUnitIntervalAroundOneHalf) {
  Rng rng(7);
  const int count = 20000;
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    const double u = rng.uniform();
    ASSERT_GT(u, 0.0);
    ASSERT_LE(u, 1.0);
    sum += u;
  }
  // Within three standard errors of 1/2 (the variance of U(0, 1] is 1/12).
  EXPECT_NEAR(sum / count, 0.5, 3.0 * std::sqrt(1.0 / 12.0 / count));
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
