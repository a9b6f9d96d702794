// vrep_depth_buffer in C++ alone: V-REP's 0..1 between the clipping planes, the bottom row
// first, clipped, computed in double and rounded once to float; bad planes refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "epuck_vrep_compat/sensors/depth_buffer.hpp"

namespace {

TEST(DepthBuffer, RowsComeBottomFirstBetweenThePlanes) {
  // 3 rows x 2 columns, row 0 at the top
  const std::vector<float> depth = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f};
  std::vector<float> out(depth.size(), -1.0f);
  evc::vrep_depth_buffer(depth.data(), out.data(), 3, 2, 1.0, 6.0);
  const std::vector<float> want = {static_cast<float>(4.0 / 5.0), 1.0f,
                                   static_cast<float>(2.0 / 5.0), static_cast<float>(3.0 / 5.0),
                                   0.0f, static_cast<float>(1.0 / 5.0)};
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(out[i], want[i]) << i;
}

TEST(DepthBuffer, ClipsOutsideThePlanesAndKeepsNaN) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> depth = {0.1f, 9.0f, inf, -inf, std::nanf("")};
  std::vector<float> out(depth.size());
  evc::vrep_depth_buffer(depth.data(), out.data(), 1, depth.size(), 0.5, 5.0);
  EXPECT_EQ(out[0], 0.0f);
  EXPECT_EQ(out[1], 1.0f);
  EXPECT_EQ(out[2], 1.0f);
  EXPECT_EQ(out[3], 0.0f);
  EXPECT_TRUE(std::isnan(out[4]));
}

TEST(DepthBuffer, RoundsTheDoubleValueOnceToFloat) {
  const float z = 1.2345678f;
  float out = 0.0f;
  evc::vrep_depth_buffer(&z, &out, 1, 1, 0.5, 5.0);
  EXPECT_EQ(out, static_cast<float>((static_cast<double>(z) - 0.5) / 4.5));
}

TEST(DepthBuffer, RefusesPlanesThatAreNotOrderedAndFinite) {
  const float z = 1.0f;
  float out = 0.0f;
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& planes : {std::pair<double, double>{2.0, 1.0}, {1.0, 1.0}, {nan, 1.0},
                             {0.0, inf}}) {
    EXPECT_THROW(evc::vrep_depth_buffer(&z, &out, 1, 1, planes.first, planes.second),
                 std::invalid_argument);
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
