// detect_blobs in C++ alone: an upright rectangle of a mask gives V-REP's values (size, centre
// from the bottom, extents between pixel centres); blobs come largest first, small ones drop.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "epuck_vrep_compat/sensors/blob_detection.hpp"

namespace {

constexpr int kWidth = 40;
constexpr int kHeight = 30;

/// Sets rows [row0, row1] × columns [col0, col1] of a one-channel mask (255: object).
void fill(std::vector<std::uint8_t>& mask, int row0, int row1, int col0, int col1) {
  for (int row = row0; row <= row1; ++row) {
    for (int col = col0; col <= col1; ++col) mask[row * kWidth + col] = 255;
  }
}

TEST(BlobDetection, AnUprightRectangleGivesVrepsValues) {
  std::vector<std::uint8_t> mask(kWidth * kHeight, 0);
  fill(mask, 5, 14, 10, 29);  // 10 rows by 20 columns, in the upper half
  const std::vector<evc::Blob> blobs = evc::detect_blobs(mask.data(), kHeight, kWidth, 1);
  ASSERT_EQ(blobs.size(), 1u);
  const evc::Blob& blob = blobs[0];
  EXPECT_DOUBLE_EQ(blob.size, 200.0 / (kWidth * kHeight));
  EXPECT_DOUBLE_EQ(blob.orientation_rad, 0.0);
  EXPECT_DOUBLE_EQ(blob.x, (19.5 + 0.5) / kWidth);  // centre column 19.5
  EXPECT_DOUBLE_EQ(blob.y, (kHeight - 9.5 - 0.5) / kHeight);  // centre row 9.5, y up
  EXPECT_DOUBLE_EQ(blob.width, 19.0 / kWidth);  // between pixel centres
  EXPECT_DOUBLE_EQ(blob.height, 9.0 / kHeight);
}

TEST(BlobDetection, BlobsComeLargestFirstAndSmallOnesDrop) {
  std::vector<std::uint8_t> mask(kWidth * kHeight, 0);
  fill(mask, 2, 4, 2, 4);  // 9 pixels
  fill(mask, 20, 27, 20, 35);  // 128 pixels
  fill(mask, 10, 10, 38, 38);  // 1 pixel
  std::vector<evc::Blob> blobs = evc::detect_blobs(mask.data(), kHeight, kWidth, 1);
  ASSERT_EQ(blobs.size(), 3u);
  EXPECT_DOUBLE_EQ(blobs[0].size, 128.0 / (kWidth * kHeight));
  EXPECT_DOUBLE_EQ(blobs[1].size, 9.0 / (kWidth * kHeight));
  EXPECT_DOUBLE_EQ(blobs[2].size, 1.0 / (kWidth * kHeight));
  blobs = evc::detect_blobs(mask.data(), kHeight, kWidth, 1, 0.5, 2.0 / (kWidth * kHeight));
  EXPECT_EQ(blobs.size(), 2u);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
