// The working scale (src/estimate/working_scale.hpp): how far the cameras saw, and the factor every
// length of the config is read at.
#include "estimate/working_scale.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace zeroreg {
namespace {

View FlatView(float depth_m, int width = 640, int height = 480) {
  View v;
  v.color = cv::Mat(height, width, CV_8UC3, cv::Scalar(100, 100, 100));
  v.depth = cv::Mat(height, width, CV_32FC1, cv::Scalar(depth_m));
  v.intrinsics = {500, 500, width / 2.0, height / 2.0, width, height};
  return v;
}

TEST(WorkingDistance, IsTheMedianValidDepthOfAllViews) {
  Scan scan;
  scan.views.push_back(FlatView(2.0f));
  View holes = FlatView(0.5f);
  holes.depth(cv::Rect(0, 0, 640, 240)).setTo(0.0f);  // half of it invalid: not counted
  scan.views.push_back(holes);
  scan.views.push_back(FlatView(3.0f));
  // 2.0 and 3.0 fill two views, 0.5 half of one: the median reading is 2.0.
  ASSERT_TRUE(WorkingDistance(scan).has_value());
  EXPECT_DOUBLE_EQ(*WorkingDistance(scan), 2.0);
}

TEST(WorkingDistance, UnknownWithoutDepth) {
  Scan scan;
  EXPECT_FALSE(WorkingDistance(scan).has_value());
  scan.views.push_back(FlatView(0.0f));
  EXPECT_FALSE(WorkingDistance(scan).has_value());
  scan.points.push_back(Eigen::Vector3d(0, 0, 1));
  EXPECT_FALSE(WorkingDistance(scan).has_value());
}

TEST(WorkingScale, IsExactlyOneInsideTheRoomsRange) {
  const ScaleConfig c;
  for (double d : {c.room_min_m, 1.3, 2.2, c.room_max_m}) EXPECT_EQ(WorkingScale(d, c), 1.0) << d;
  EXPECT_EQ(WorkingScale(std::nullopt, c), 1.0);
  // Just outside the range the ratio rounds to 1: k does not jump at the range's ends.
  EXPECT_EQ(WorkingScale(0.95 * c.room_min_m, c), 1.0);
  EXPECT_EQ(WorkingScale(1.05 * c.room_max_m, c), 1.0);
}

TEST(WorkingScale, FollowsTheDistanceOutsideInQuarterOctaves) {
  const ScaleConfig c;
  EXPECT_DOUBLE_EQ(WorkingScale(0.25 * c.room_min_m, c), 0.25);
  EXPECT_DOUBLE_EQ(WorkingScale(0.1 * c.room_min_m, c), std::exp2(-13.0 / 4.0));  // 0.105
  EXPECT_DOUBLE_EQ(WorkingScale(4.0 * c.room_max_m, c), 4.0);
  for (double d = 0.02; d < 60; d *= 1.07) {
    const double k = WorkingScale(d, c);
    const double exact = d < c.room_min_m   ? d / c.room_min_m
                         : d > c.room_max_m ? d / c.room_max_m
                                            : 1.0;
    EXPECT_LE(std::abs(std::log2(k / exact)), 0.125 + 1e-12) << d;  // within an eighth octave
    EXPECT_DOUBLE_EQ(4 * std::log2(k), std::round(4 * std::log2(k))) << d;
  }
}

TEST(WorkingScale, SetDistanceOrOff) {
  ScaleConfig c;
  c.working_distance_m = 0.5 * c.room_min_m;
  EXPECT_DOUBLE_EQ(WorkingScale(2.0, c), 0.5);
  c.automatic = false;
  EXPECT_EQ(WorkingScale(0.05, c), 1.0);
}

// Structured-light depth: its noise in inverse depth is a constant of the sensor, so a copy s times
// the size (distance s d, noise a / s) is read at k = s; the frames the defaults were measured on
// (the corners of what they span) at k = 1.
TEST(WorkingScale, StructuredLightNoiseGivesTheScale) {
  const ScaleConfig c;
  const double a_lo = c.structured_light_noise_min_at_1m_m;
  const double a_hi = c.structured_light_noise_max_at_1m_m;
  const double d_lo = c.structured_light_min_m, d_hi = c.structured_light_max_m;
  for (const ScaleEvidence& e : std::vector<ScaleEvidence>{
           {d_lo, a_lo}, {d_lo, a_hi}, {d_hi, a_lo}, {d_hi, a_hi}, {1.8, 0.0017}}) {
    EXPECT_EQ(WorkingScale(e, c), 1.0) << *e.distance_m << " " << *e.noise_at_1m_m;
    for (double s : {0.25, 4.0, 1.0 / 16}) {
      const ScaleEvidence copy{s * *e.distance_m, *e.noise_at_1m_m / s};
      EXPECT_DOUBLE_EQ(WorkingScale(copy, c), s) << *e.distance_m << " " << s;
    }
    // 0.1 is no quarter octave: one of the two around it (2^(-13/4) = 0.105 where the noise is
    // the middle of the measured range, 2^(-14/4) = 0.088 at its noisier end). Times 0.1 is not
    // exact in floating point: the copy of a corner is taken just inside the range.
    const double d = std::clamp(*e.distance_m, 1.001 * d_lo, 0.999 * d_hi);
    const ScaleEvidence tenth{0.1 * d, *e.noise_at_1m_m / 0.1};
    const double k = WorkingScale(tenth, c);
    EXPECT_TRUE(k == std::exp2(-13.0 / 4.0) || k == std::exp2(-14.0 / 4.0)) << k;
  }
  EXPECT_DOUBLE_EQ(WorkingScale(ScaleEvidence{0.18, 0.017}, c), std::exp2(-13.0 / 4.0));
  // The distance band alone reads the large copy of a kitchen seen from 2 m as a room at 5 m.
  EXPECT_DOUBLE_EQ(WorkingScale(ScaleEvidence{8.0, 0.0017 / 4}, c), 4.0);
  EXPECT_DOUBLE_EQ(WorkingScale(std::optional<double>(8.0), c), std::exp2(0.75));
}

// Depth whose relative noise a d lies outside what the structured-light frames span (the
// HoloLens' time of flight, a structured-light sensor much nearer or farther than they were) has
// no sensor constant to read: the distance band decides, as without the noise.
TEST(WorkingScale, OtherDepthKeepsTheDistanceBand) {
  const ScaleConfig c;
  for (double d : {0.05, 0.2, 1.3, 2.5, 4.7, 9.0, 30.0}) {
    for (double a : {0.0001, 0.0004, 0.0015}) {
      const double relative = a * d;
      if (relative >= c.structured_light_noise_min_at_1m_m * c.structured_light_min_m &&
          relative <= c.structured_light_noise_max_at_1m_m * c.structured_light_max_m) {
        continue;
      }
      EXPECT_EQ(WorkingScale(ScaleEvidence{d, a}, c), WorkingScale(std::optional<double>(d), c))
          << d << " " << a;
    }
    EXPECT_EQ(WorkingScale(ScaleEvidence{d, std::nullopt}, c),
              WorkingScale(std::optional<double>(d), c));
  }
  ScaleConfig off = c;
  off.structured_light_noise_min_at_1m_m = 0;
  EXPECT_DOUBLE_EQ(WorkingScale(ScaleEvidence{8.0, 0.0017 / 4}, off), std::exp2(0.75));
  ScaleConfig set = c;  // a set working distance decides alone
  set.working_distance_m = 0.5;
  EXPECT_DOUBLE_EQ(WorkingScale(ScaleEvidence{8.0, 0.0017 / 4}, set), 0.5);
}

TEST(PairWorkingDistance, GeometricMeanOrTheKnownOne) {
  EXPECT_DOUBLE_EQ(*PairWorkingDistance(1.0, 4.0), 2.0);
  EXPECT_DOUBLE_EQ(*PairWorkingDistance(std::nullopt, 4.0), 4.0);
  EXPECT_FALSE(PairWorkingDistance(std::nullopt, std::nullopt).has_value());
}

TEST(InWorkingUnits, DividesEveryLengthByK) {
  Scan scan;
  View v = FlatView(0.5f);
  v.depth.at<float>(0, 0) = 0.0f;
  v.T_scan_camera(0, 3) = 0.2;
  v.T_scan_camera(2, 3) = -0.1;
  v.T_world_camera_gt = Transform::Identity();
  v.T_world_camera_gt->operator()(1, 3) = 0.3;
  scan.views.push_back(v);
  scan.points.push_back(Eigen::Vector3d(0.1, 0.2, 0.3));
  scan.T_world_scan_gt = Transform::Identity();
  scan.T_world_scan_gt->operator()(0, 3) = 0.4;
  const Scan out = InWorkingUnits(scan, 0.25);
  EXPECT_FLOAT_EQ(out.views[0].depth.at<float>(10, 10), 2.0f);
  EXPECT_EQ(out.views[0].depth.at<float>(0, 0), 0.0f);  // invalid stays invalid
  EXPECT_DOUBLE_EQ(out.views[0].T_scan_camera(0, 3), 0.8);
  EXPECT_DOUBLE_EQ(out.views[0].T_scan_camera(2, 3), -0.4);
  EXPECT_DOUBLE_EQ((*out.views[0].T_world_camera_gt)(1, 3), 1.2);
  EXPECT_DOUBLE_EQ(out.points[0].z(), 1.2);
  EXPECT_DOUBLE_EQ((*out.T_world_scan_gt)(0, 3), 1.6);
  // The input is not touched (the depth is a copy, not a shared buffer).
  EXPECT_FLOAT_EQ(scan.views[0].depth.at<float>(10, 10), 0.5f);
  // k = 1 is the scan itself.
  const Scan same = InWorkingUnits(scan, 1.0);
  EXPECT_EQ(same.views[0].depth.data, scan.views[0].depth.data);
}

}  // namespace
}  // namespace zeroreg
