// The same scene at another scale is the same registration problem (docs/CONFIG.md, "Any
// scale"): a copy of a real pair with every depth reading and pose translation multiplied by s
// (same images and intrinsics) gives the same verdict and the estimate's translation times s.
// scripts/bench-scale.py measures it on whole lists; this is its small version.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "eval/metrics.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

Scan Frame(int id) { return LoadScan(testing::RedkitchenDir() + "@" + std::to_string(id)); }

Scan Scaled(const Scan& scan, double s) {
  Scan out = scan;
  for (View& v : out.views) {
    cv::Mat depth;  // a new buffer: the copy shares the original's
    v.depth.convertTo(depth, CV_32F, s);
    v.depth = depth;
    v.T_scan_camera.topRightCorner<3, 1>() *= s;
    if (v.T_world_camera_gt) v.T_world_camera_gt->topRightCorner<3, 1>() *= s;
  }
  if (out.T_world_scan_gt) out.T_world_scan_gt->topRightCorner<3, 1>() *= s;
  return out;
}

Transform GroundTruth(const Scan& source, const Scan& target) {
  return target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
}

// The config with the working distance set so that the working scale is exactly k.
PipelineConfig AtScale(double k) {
  PipelineConfig c;
  c.scale.working_distance_m = k < 1 ? k * c.scale.room_min_m : k * c.scale.room_max_m;
  return c;
}

// With the working scale equal to s (powers of two: scaling and unscaling are exact in floating
// point), the copy is registered bit for bit as the original: the pipeline sees the scans only in
// working units, and every length it reports is converted back.
TEST(ScaleEquivariance, ExactWhenTheWorkingScaleIsTheScale) {
  const Scan source = Frame(60), target = Frame(0);
  const RegistrationResult original = Register(source, target, AtScale(1.0));
  ASSERT_TRUE(original.valid) << original.reason;
  for (double s : {0.25, 4.0}) {
    SCOPED_TRACE(s);
    const RegistrationResult r = Register(Scaled(source, s), Scaled(target, s), AtScale(s));
    EXPECT_EQ(r.valid, original.valid);
    EXPECT_EQ(r.path, original.path) << r.reason << "\n" << original.reason;
    EXPECT_EQ(r.num_inliers, original.num_inliers);
    EXPECT_EQ(r.refusal.test, original.refusal.test);
    const Eigen::Matrix3d R = r.T_target_source.topLeftCorner<3, 3>();
    const Eigen::Matrix3d R0 = original.T_target_source.topLeftCorner<3, 3>();
    EXPECT_TRUE(R == R0) << R;
    for (int i = 0; i < 3; ++i) {
      EXPECT_DOUBLE_EQ(r.T_target_source(i, 3), s * original.T_target_source(i, 3));
    }
    EXPECT_DOUBLE_EQ(r.inlier_spread_m, s * original.inlier_spread_m);
    EXPECT_DOUBLE_EQ(r.verification.residual_rms_m, s * original.verification.residual_rms_m);
    EXPECT_DOUBLE_EQ(r.verification.score, original.verification.score);
    ASSERT_EQ(r.source_objects.size(), original.source_objects.size());
    for (size_t i = 0; i < r.source_objects.size(); ++i) {
      EXPECT_TRUE(r.source_objects[i].centroid.isApprox(s * original.source_objects[i].centroid));
    }
    EXPECT_NE(r.reason.find("working scale"), std::string::npos) << r.reason;
  }
}

// The working scale measured from the data is the scale itself for structured-light depth (its
// noise in inverse depth is a constant of the sensor; a copy's is 1 / s times it): the copies at
// s = 0.25 and 4 are registered bit for bit as the kitchen, with no setting.
TEST(ScaleEquivariance, StructuredLightCopiesAreTheSameProblem) {
  const Scan source = Frame(60), target = Frame(0);
  const RegistrationResult original = Register(source, target);
  ASSERT_TRUE(original.valid) << original.reason;
  for (double s : {0.25, 4.0}) {
    SCOPED_TRACE(s);
    const RegistrationResult r = Register(Scaled(source, s), Scaled(target, s));
    EXPECT_EQ(r.valid, original.valid);
    EXPECT_EQ(r.path, original.path) << r.reason << "\n" << original.reason;
    EXPECT_EQ(r.num_inliers, original.num_inliers);
    const Eigen::Matrix3d R = r.T_target_source.topLeftCorner<3, 3>();
    const Eigen::Matrix3d R0 = original.T_target_source.topLeftCorner<3, 3>();
    EXPECT_TRUE(R == R0) << R;
    for (int i = 0; i < 3; ++i) {
      EXPECT_DOUBLE_EQ(r.T_target_source(i, 3), s * original.T_target_source(i, 3));
    }
    EXPECT_DOUBLE_EQ(r.verification.score, original.verification.score);
  }
}

// The working scale measured from the data: a kitchen ten times smaller (seen from 12-25 cm, as a
// phone sees a door handle) and four times larger are registered as well as the kitchen, with
// errors in proportion.
TEST(ScaleEquivariance, MeasuredScaleRegistersSmallAndLargeCopies) {
  const Scan source = Frame(60), target = Frame(0);
  const Transform gt = GroundTruth(source, target);
  for (double s : {0.1, 4.0}) {
    SCOPED_TRACE(s);
    const Scan scaled_source = Scaled(source, s), scaled_target = Scaled(target, s);
    const RegistrationResult r = Register(scaled_source, scaled_target);
    EXPECT_TRUE(r.valid) << r.reason;
    EXPECT_LT(RotationErrorDeg(r.T_target_source, GroundTruth(scaled_source, scaled_target)), 5.0);
    EXPECT_LT(TranslationErrorM(r.T_target_source, GroundTruth(scaled_source, scaled_target)),
              0.05 * s);
    EXPECT_NEAR((GroundTruth(scaled_source, scaled_target).topRightCorner<3, 1>() / s -
                 gt.topRightCorner<3, 1>())
                    .norm(),
                0.0, 1e-9);
  }
}

// Without the working scale (scale.automatic = false) the room's lengths are used at every scale:
// the test above is not passed by accident.
TEST(ScaleEquivariance, RoomLengthsFailTheSmallCopy) {
  const Scan source = Frame(60), target = Frame(0);
  PipelineConfig c;
  c.scale.automatic = false;
  const Scan scaled_source = Scaled(source, 0.1), scaled_target = Scaled(target, 0.1);
  const RegistrationResult r = Register(scaled_source, scaled_target, c);
  const bool right =
      RotationErrorDeg(r.T_target_source, GroundTruth(scaled_source, scaled_target)) < 5.0 &&
      TranslationErrorM(r.T_target_source, GroundTruth(scaled_source, scaled_target)) < 0.005;
  EXPECT_FALSE(r.valid && right) << r.reason;
}

// Scans prepared one by one get their own working scale (the kitchen at s = 0.25 read by the
// distance alone: frame 0 is seen from 0.47 m, k = 0.5, frame 60 from 0.42 m, k = 0.42); a pair
// registers both at the pair's (0.42), preparing again the one whose own differs: the same
// result as registering the two scans at once.
TEST(ScaleEquivariance, PreparedScansMeetAtThePairsScale) {
  const Scan source = Scaled(Frame(60), 0.25), target = Scaled(Frame(0), 0.25);
  PipelineConfig by_distance;
  by_distance.scale.structured_light_noise_min_at_1m_m = 0;  // else both are read at 0.25
  const Pipeline pipeline{by_distance};
  const PreparedScan s = pipeline.Prepare(source, /*as_target=*/false);
  const PreparedScan t = pipeline.Prepare(target);
  EXPECT_EQ(s.scan().views[0].depth.data, source.views[0].depth.data);  // the scan as given
  const RegistrationResult prepared = pipeline.Register(s, t);
  const RegistrationResult direct = pipeline.Register(source, target);
  EXPECT_TRUE(direct.valid) << direct.reason;
  EXPECT_EQ(prepared.valid, direct.valid);
  EXPECT_EQ(prepared.path, direct.path);
  EXPECT_TRUE(prepared.T_target_source == direct.T_target_source);
}

// A phone's frames: portrait (the landscape frame turned a quarter turn, intrinsics with it),
// depth from a 256x192 sensor upsampled to the colour size, and the scene seen from 12-25 cm
// (the kitchen at s = 0.1: every reading below the earlier 0.3 m cut-offs).
Scan PhoneFrame(const Scan& scan, int interpolation) {
  Scan out = scan;
  for (View& v : out.views) {
    const int w = v.color.cols, h = v.color.rows;
    cv::Mat color, depth, low;
    cv::rotate(v.color, color, cv::ROTATE_90_CLOCKWISE);
    cv::rotate(v.depth, depth, cv::ROTATE_90_CLOCKWISE);
    cv::resize(depth, low, cv::Size(192, 256), 0, 0, cv::INTER_NEAREST);
    cv::resize(low, depth, color.size(), 0, 0, interpolation);
    v.color = color;
    v.depth = depth;
    // Pixel (x, y) goes to (h - 1 - y, x): camera axes x' = -y, y' = x, z' = z.
    Transform M = Transform::Identity();
    M.topLeftCorner<3, 3>() << 0, 1, 0, -1, 0, 0, 0, 0, 1;
    v.T_scan_camera = v.T_scan_camera * M;
    const Intrinsics k = v.intrinsics;
    v.intrinsics = {k.fy, k.fx, h - 1 - k.cy, k.cx, h, w};
  }
  return out;
}

class CloseRangePhone : public ::testing::TestWithParam<int> {};

TEST_P(CloseRangePhone, PortraitUpsampledDepthAtFifteenCentimetres) {
  const double s = 0.1;
  const Scan source = PhoneFrame(Scaled(Frame(20), s), GetParam());
  const Scan target = PhoneFrame(Scaled(Frame(0), s), GetParam());
  ASSERT_EQ(source.views[0].depth.cols, 480);
  const RegistrationResult r = Register(source, target);
  const Transform gt = GroundTruth(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.05 * s);
}

INSTANTIATE_TEST_SUITE_P(Upsampling, CloseRangePhone,
                         ::testing::Values(cv::INTER_NEAREST, cv::INTER_LINEAR));

}  // namespace
}  // namespace zeroreg
