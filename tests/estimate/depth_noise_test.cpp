// The depth-noise measurement (src/estimate/depth_noise.hpp) on synthetic depth images with a
// known noise level, on real frames of known sensors, and its use in ICP's sampling grid.
#include "estimate/depth_noise.hpp"

#include <gtest/gtest.h>

#include "estimate/icp.hpp"
#include "estimate/lift.hpp"
#include "noisy_wall.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing::NoisyWall;

TEST(DepthNoise, MeasuresTheNoiseItWasGiven) {
  for (const double a : {0.0015, 0.005, 0.01}) {
    const std::optional<double> measured = MeasureDepthNoiseAt1m(NoisyWall(a, 7));
    ASSERT_TRUE(measured.has_value());
    EXPECT_NEAR(*measured, a, 0.1 * a) << a;
  }
  // Noise-free depth measures (almost) nothing: the plane and the box's edges are not noise.
  EXPECT_LT(*MeasureDepthNoiseAt1m(NoisyWall(0.0, 7)), 1e-5);
}

TEST(DepthNoise, ScanTakesTheMedianViewAndNeedsDepth) {
  Scan scan;
  for (const double a : {0.002, 0.01, 0.004}) scan.views.push_back(NoisyWall(a, 3));
  EXPECT_NEAR(*MeasureDepthNoiseAt1m(scan), 0.004, 0.0004);
  View empty = NoisyWall(0.002, 3);
  empty.depth.setTo(0.0f);
  EXPECT_FALSE(MeasureDepthNoiseAt1m(empty).has_value());
  EXPECT_FALSE(MeasureDepthNoiseAt1m(Scan()).has_value());
}

// Kinect v1 frames measure close to its published 1.5 mm at 1 m (Khoshelham & Elberink 2012),
// below the "noisy" line that changes ICP's sampling.
TEST(DepthNoise, KinectFramesMeasureAboutOneAndAHalfMillimetres) {
  for (const int frame : {0, 500}) {
    const Scan scan = LoadScan(testing::RedkitchenDir() + "@" + std::to_string(frame));
    const std::optional<double> a = MeasureDepthNoiseAt1m(scan);
    ASSERT_TRUE(a.has_value());
    EXPECT_GT(*a, 0.0012);
    EXPECT_LT(*a, 0.0022);
    EXPECT_LT(*a, kNoisyDepthAt1mM);
  }
}

// ICP samples every other pixel of quiet depth and every 4th of noisy depth (at 640 px wide);
// an explicit refine.pixel_stride is used whatever the noise.
TEST(DepthNoise, IcpSamplesNoisyDepthOnTheSparserGrid) {
  const std::vector<IcpStage> stages = IcpSchedule(RefineConfig(), DepthModel());
  const double voxel = RefineConfig().voxel_m;
  const auto points = [&](double noise, int stride) {
    Scan scan;
    scan.views.push_back(NoisyWall(noise, 11));
    return ScanIcpGeometry(scan, stages, /*as_target=*/false, stride).NumPoints(voxel);
  };
  EXPECT_EQ(points(0.0015, 0), points(0.0015, 2));
  EXPECT_EQ(points(0.006, 0), points(0.006, 4));
  EXPECT_LT(points(0.006, 0), points(0.006, 2));
}

// Lifting (LiftPixel) with the view's measured noise (LiftForView): noise alone no longer makes
// edges, real depth jumps (the box 0.5 m in front of the wall) still do.
TEST(DepthNoise, LiftingIgnoresNoiseButNotRealEdges) {
  const View view = NoisyWall(0.01, 5);
  const ViewLift plain;
  const ViewLift measured = LiftForView(LiftConfig(), DepthModel(), view);
  EXPECT_NEAR(measured.view_depth_noise_at_1m_m, 0.01, 0.001);
  const auto lifted = [&](const ViewLift& lift, int x0, int x1) {
    int n = 0;
    for (int y = 8; y < 472; y += 4) {
      for (int x = x0; x < x1; x += 4) {
        n += LiftPixel(view, Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y)), lift)
                 ? 1
                 : 0;
      }
    }
    return n;
  };
  // The far, noisy right part of the wall (2.4-3 m: sigma 6-9 cm): mostly refused as "edges"
  // without the noise floor, mostly lifted with it.
  const int samples = 116 * 38;
  EXPECT_LT(lifted(plain, 480, 632), samples / 2);
  EXPECT_GT(lifted(measured, 480, 632), samples * 9 / 10);
  // Pixels on the box's side edges (x = 251 and 399 +- 1 px) stay refused.
  for (const int x : {250, 251, 252, 398, 399, 400}) {
    EXPECT_FALSE(LiftPixel(view, Eigen::Vector2f(static_cast<float>(x), 300.0f), measured)) << x;
  }
}

// On a real Kinect v1 frame the noise floor is below 5 % of the depth wherever the depth is under
// 5 m, so lifting is exactly what it was without it.
TEST(DepthNoise, KinectFramesLiftAsBefore) {
  const Scan scan = LoadScan(testing::RedkitchenDir() + "@0");
  const View& view = scan.views[0];
  const ViewLift plain;
  const ViewLift measured = LiftForView(LiftConfig(), DepthModel(), view);
  ASSERT_GT(measured.view_depth_noise_at_1m_m, 0.0);
  int compared = 0;
  for (int y = 0; y < view.depth.rows; y += 2) {
    for (int x = 0; x < view.depth.cols; x += 2) {
      if (!(view.depth.at<float>(y, x) < 5.0f)) continue;
      const Eigen::Vector2f pixel(static_cast<float>(x), static_cast<float>(y));
      ASSERT_EQ(LiftPixel(view, pixel, plain).has_value(),
                LiftPixel(view, pixel, measured).has_value())
          << x << " " << y;
      ++compared;
    }
  }
  EXPECT_GT(compared, 50000);
}

}  // namespace
}  // namespace zeroreg
