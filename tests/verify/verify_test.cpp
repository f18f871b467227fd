// The geometric verdict (src/verify) on synthetic RGB-D scans with exact poses: depth images are
// ray-cast from an analytic scene (planes and boxes), so the true transform is known exactly.
#include "verify/verify.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace zeroreg {
namespace {

// Axis-aligned box [lo, hi] (world frame, metres). A plane is a thin, large box.
struct Box {
  Eigen::Vector3d lo, hi;
};

// Nearest positive ray parameter of a box hit (slab method), or infinity.
double HitBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d(k)) < 1e-12) {
      if (o(k) < b.lo(k) || o(k) > b.hi(k)) return std::numeric_limits<double>::infinity();
      continue;
    }
    double a = (b.lo(k) - o(k)) / d(k), c = (b.hi(k) - o(k)) / d(k);
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0 > 0 ? t0 : std::numeric_limits<double>::infinity();
}

// A one-view scan of `scene` seen from camera pose T_world_camera (x right, y down, z forward),
// 320x240 pixels times `scale` (same field of view at any scale). Grey surfaces, or with
// `patterned` a brightness that varies over the world (the same surface point has the same
// brightness from every camera).
Scan Render(const std::vector<Box>& scene, const Transform& T_world_camera, int scale = 1,
            bool patterned = false) {
  const int width = 320 * scale, height = 240 * scale;
  const double f = 320.0 * scale, cx = (width - 1) / 2.0, cy = (height - 1) / 2.0;
  View v;
  v.name = "synthetic";
  v.intrinsics = {f, f, cx, cy, width, height};
  v.color = cv::Mat(height, width, CV_8UC3, cv::Scalar(128, 128, 128));
  v.depth = cv::Mat(height, width, CV_32FC1, cv::Scalar(0.0f));
  const Eigen::Matrix3d R = T_world_camera.topLeftCorner<3, 3>();
  const Eigen::Vector3d o = T_world_camera.topRightCorner<3, 1>();
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d ray_camera((x - cx) / f, (y - cy) / f, 1.0);
      const Eigen::Vector3d d = R * ray_camera;
      double t = std::numeric_limits<double>::infinity();
      for (const Box& b : scene) t = std::min(t, HitBox(b, o, d));
      if (t < 8.0) v.depth.at<float>(y, x) = static_cast<float>(t);  // z = t (ray_camera.z = 1)
      if (patterned && t < 8.0) {
        const Eigen::Vector3d w = o + t * d;
        const double level =
            128.0 + 100.0 * std::sin(3.0 * (w.x() + w.z())) * std::cos(2.0 * w.y());
        v.color.at<cv::Vec3b>(y, x) = cv::Vec3b::all(static_cast<unsigned char>(level));
      }
    }
  }
  Scan s;
  s.name = "synthetic";
  s.views.push_back(v);
  return s;
}

// Camera at `position` turned by `yaw_deg` about the world's vertical (y) axis.
Transform Pose(double yaw_deg, const Eigen::Vector3d& position) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.topRightCorner<3, 1>() = position;
  return T;
}

// A room: floor (y = 1.2, y points down), back wall, two side walls, a table-sized box and a
// cabinet.
std::vector<Box> Room() {
  return {{{-3, 1.2, -1}, {3, 1.3, 6}},        {{-3, -1.5, 5}, {3, 1.3, 5.1}},
          {{-3.1, -1.5, -1}, {-3, 1.3, 6}},    {{3, -1.5, -1}, {3.1, 1.3, 6}},
          {{-0.6, 0.4, 2.5}, {0.4, 1.2, 3.3}}, {{1.2, -0.6, 3.6}, {2.2, 1.2, 4.4}}};
}

// A corridor along z: floor and two walls, open at both ends beyond the sensor's range.
std::vector<Box> Corridor() {
  return {{{-1, 1.2, -20}, {1, 1.3, 20}},
          {{-1.1, -1.5, -20}, {-1, 1.3, 20}},
          {{1, -1.5, -20}, {1.1, 1.3, 20}}};
}

struct Pair {
  Scan source, target;
  Transform T_target_source;
};

Pair MakePair(const std::vector<Box>& scene, int scale = 1) {
  const Transform P_target = Pose(0, {0, 0, 0});
  const Transform P_source = Pose(12, {0.3, 0.0, 0.4});
  return {Render(scene, P_source, scale), Render(scene, P_target, scale),
          P_target.inverse() * P_source};
}

TEST(Verify, CorrectTransformPasses) {
  const Pair p = MakePair(Room());
  const VerificationResult v =
      VerifyRegistration(p.source, p.target, p.T_target_source, VerifyConfig(), DepthModel());
  EXPECT_TRUE(v.ran);
  EXPECT_TRUE(v.passed) << v.reason;
  EXPECT_GT(v.overlap, 0.6);
  EXPECT_LT(v.violation, 0.01);
  // Not zero: the depth is read at the nearest pixel, on slanted surfaces (the floor) that is
  // millimetres to a centimetre off.
  EXPECT_LT(v.residual_rms_m, 0.015);
  EXPECT_FALSE(v.degenerate) << v.reason;
}

// Where the depth agrees, the images agree too under the right transform (same surface points),
// in the order of their brightness whatever the exposure: rank correlation near 1; with one image's
// brightness reversed, near -1; on uniformly grey surfaces there is no order to compare (NaN).
TEST(Verify, BrightnessRankCorrelationAtTheAgreeingSamples) {
  const Transform P_target = Pose(0, {0, 0, 0}), P_source = Pose(12, {0.3, 0.0, 0.4});
  const Transform T = P_target.inverse() * P_source;
  const Scan source = Render(Room(), P_source, 1, true), target = Render(Room(), P_target, 1, true);
  const VerificationResult right =
      VerifyRegistration(source, target, T, VerifyConfig(), DepthModel());
  ASSERT_TRUE(right.passed) << right.reason;
  EXPECT_GT(right.brightness_rank_correlation, 0.9);
  Scan darker = target;  // another exposure: the order of brightness stays
  darker.views[0].color = target.views[0].color * 0.5;
  EXPECT_GT(VerifyRegistration(source, darker, T, VerifyConfig(), DepthModel())
                .brightness_rank_correlation,
            0.9);
  Scan reversed = target;
  cv::subtract(cv::Scalar::all(255), target.views[0].color, reversed.views[0].color);
  EXPECT_LT(VerifyRegistration(source, reversed, T, VerifyConfig(), DepthModel())
                .brightness_rank_correlation,
            -0.9);
  const Pair grey = MakePair(Room());
  EXPECT_TRUE(std::isnan(VerifyRegistration(grey.source, grey.target, grey.T_target_source,
                                            VerifyConfig(), DepthModel())
                             .brightness_rank_correlation));
}

// The dangerous case: a transform that keeps the floor aligned (here: turned 35 deg
// about the floor's normal and shifted along the floor), so floor texture would give inliers, but
// puts the walls and furniture where the other camera saw free space.
TEST(Verify, TransformAligningOnlyTheFloorFails) {
  const Pair p = MakePair(Room());
  Transform slide = Transform::Identity();
  slide.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(35 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d pivot(0, 1.2, 3);
  slide.topRightCorner<3, 1>() = pivot - slide.topLeftCorner<3, 3>() * pivot +
                                 Eigen::Vector3d(0.4, 0, -0.3);  // stays on the floor plane
  const VerificationResult v = VerifyRegistration(p.source, p.target, slide * p.T_target_source,
                                                  VerifyConfig(), DepthModel());
  EXPECT_FALSE(v.passed) << v.reason;
  EXPECT_GT(v.violation, 0.1) << v.reason;
}

TEST(Verify, WrongByThirtyCentimetresFails) {
  const Pair p = MakePair(Room());
  Transform shift = Transform::Identity();
  shift.topRightCorner<3, 1>() = Eigen::Vector3d(0.3, 0, 0);
  const VerificationResult v = VerifyRegistration(p.source, p.target, shift * p.T_target_source,
                                                  VerifyConfig(), DepthModel());
  EXPECT_FALSE(v.passed) << v.reason;
}

TEST(Verify, CorridorIsFlaggedDegenerate) {
  const Pair p = MakePair(Corridor());
  const VerificationResult v =
      VerifyRegistration(p.source, p.target, p.T_target_source, VerifyConfig(), DepthModel());
  EXPECT_TRUE(v.degenerate) << v.reason;
  EXPECT_LT(v.probe_contradicted, VerifyConfig().min_probe_contradicted);
}

TEST(Verify, RoomIsNotDegenerateButASinglePlaneIs) {
  const Pair room = MakePair(Room());
  EXPECT_FALSE(VerifyRegistration(room.source, room.target, room.T_target_source, VerifyConfig(),
                                  DepthModel())
                   .degenerate);
  const Pair plane = MakePair({{{-20, 1.2, -20}, {20, 1.3, 20}}});
  EXPECT_TRUE(VerifyRegistration(plane.source, plane.target, plane.T_target_source, VerifyConfig(),
                                 DepthModel())
                  .degenerate);
}

// What decides whether ICP's result is kept (register.cpp, Refine): the check's score. An ICP
// that slid 20 cm along the back wall (an office cubicle) scores lower than the
// estimate it started from, so the estimate stays.
TEST(Verify, SlidingAlongAWallScoresLowerThanTheTruth) {
  const Pair p = MakePair(Room());
  Transform slide = Transform::Identity();
  slide.topRightCorner<3, 1>() = Eigen::Vector3d(0.2, 0, 0);  // along the back wall (x)
  const VerifyConfig c;
  const double truth =
      VerifyRegistration(p.source, p.target, p.T_target_source, c, DepthModel()).score;
  const double slid =
      VerifyRegistration(p.source, p.target, slide * p.T_target_source, c, DepthModel()).score;
  EXPECT_LT(slid, truth - 0.05);
}

TEST(Verify, NoDepthIsTooLittleToVerify) {
  Pair p = MakePair(Room());
  p.source.views[0].depth.setTo(0.0f);
  const VerificationResult v =
      VerifyRegistration(p.source, p.target, p.T_target_source, VerifyConfig(), DepthModel());
  EXPECT_FALSE(v.passed);
  EXPECT_LT(std::min(v.source_samples, v.target_samples), VerifyConfig().min_points) << v.reason;
}

// The default sampling grid follows the image size (verify.pixel_stride = 0, PixelGrid): the same
// scene seen at 640x480 and 1280x960 gives about the same number of samples and the same verdict,
// while a fixed stride samples the larger image four times as densely.
TEST(Verify, SamplesFollowTheImageSize) {
  const Pair small = MakePair(Room(), 2), large = MakePair(Room(), 4);
  const size_t n_small = SampleSurface(small.target, VerifyConfig(), DepthModel()).size();
  const size_t n_large = SampleSurface(large.target, VerifyConfig(), DepthModel()).size();
  ASSERT_GT(n_small, 5000u);
  EXPECT_NEAR(static_cast<double>(n_large) / static_cast<double>(n_small), 1.0, 0.05);
  VerifyConfig fixed;
  fixed.pixel_stride = 4;
  EXPECT_EQ(SampleSurface(small.target, fixed, DepthModel()).size(), n_small);  // 640 px: auto = 4
  EXPECT_NEAR(static_cast<double>(SampleSurface(large.target, fixed, DepthModel()).size()) /
                  static_cast<double>(n_small),
              4.0, 0.2);
  const VerificationResult a = VerifyRegistration(small.source, small.target, small.T_target_source,
                                                  VerifyConfig(), DepthModel());
  const VerificationResult b = VerifyRegistration(large.source, large.target, large.T_target_source,
                                                  VerifyConfig(), DepthModel());
  EXPECT_TRUE(a.passed) << a.reason;
  EXPECT_TRUE(b.passed) << b.reason;
  EXPECT_NEAR(a.overlap, b.overlap, 0.03);
}

TEST(Verify, SameInputSameResult) {
  const Pair p = MakePair(Room());
  const VerificationResult a = VerifyRegistration(p.source, p.target, p.T_target_source, {}, {});
  const VerificationResult b = VerifyRegistration(p.source, p.target, p.T_target_source, {}, {});
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(a.reason, b.reason);
}

}  // namespace
}  // namespace zeroreg
