// Pixel grids (src/estimate/lift.hpp, PixelGrid): a positive stride is used as given; 0 follows
// the image width so that a view gives about the same number of samples at any resolution.
#include "estimate/lift.hpp"

#include <gtest/gtest.h>

namespace zeroreg {
namespace {

TEST(PixelGrid, AutoStrideKeepsTheColumnsAtMostTheLimit) {
  const PixelGrid grid;               // auto, kGridColumns = 160
  EXPECT_EQ(grid.StrideFor(640), 4);  // Kinect v1 (redkitchen, TUM cabinet): as before
  EXPECT_EQ(grid.StrideFor(540), 4);  // HoloLens (hololens-office): as before
  EXPECT_EQ(grid.StrideFor(1280), 8);
  EXPECT_EQ(grid.StrideFor(1920), 12);
  EXPECT_EQ(grid.StrideFor(320), 2);
  EXPECT_EQ(grid.StrideFor(100), 1);
  for (int width = 16; width <= 4096; width += 7) {
    const int stride = grid.StrideFor(width);
    EXPECT_LE((width + stride - 1) / stride, kGridColumns) << width;  // at most the limit ...
    if (stride > 1) {  // ... and the smallest stride that is
      EXPECT_GT((width + stride - 2) / (stride - 1), kGridColumns) << width;
    }
  }
}

TEST(PixelGrid, FixedStrideIgnoresTheImageSize) {
  EXPECT_EQ((PixelGrid{3}).StrideFor(1280), 3);
  EXPECT_EQ((PixelGrid{1}).StrideFor(640), 1);
  EXPECT_EQ((PixelGrid{0, 320}).StrideFor(640), 2);  // ICP's grid
  EXPECT_EQ((PixelGrid{0, 320}).StrideFor(1280), 4);
}

TEST(PixelGrid, ScanPointsUsesEachViewsOwnStride) {
  Scan scan;
  for (int width : {640, 1280}) {
    View view;
    view.intrinsics = {500, 500, width / 2.0, width * 0.375, width, width * 3 / 4};
    view.depth = cv::Mat(width * 3 / 4, width, CV_32F, cv::Scalar(1.5f));
    view.color = cv::Mat(width * 3 / 4, width, CV_8UC3, cv::Scalar(0, 0, 0));
    scan.views.push_back(view);
  }
  // 160 x 120 samples from each view.
  EXPECT_EQ(ScanPoints(scan, PixelGrid{}).size(), 2u * 160u * 120u);
  EXPECT_EQ(ScanPoints(scan, PixelGrid{4}).size(), 160u * 120u + 320u * 240u);
}

}  // namespace
}  // namespace zeroreg
