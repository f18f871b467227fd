// The --method sift / orb baselines (src/eval/methods.cpp) on a real redkitchen pair.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/methods.hpp"
#include "eval/metrics.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

struct RealPair {
  Scan source, target;
  Transform gt;
};

// Redkitchen frames 20 (source) -> 0 (target), ground truth from the dataset poses.
RealPair Redkitchen20To0() {
  const auto dataset = OpenDataset(testing::RedkitchenDir());
  RealPair p;
  View source = dataset->LoadFrame(20), target = dataset->LoadFrame(0);
  p.gt = target.T_world_camera_gt->inverse() * *source.T_world_camera_gt;
  p.source = ScanFromView(source);
  p.target = ScanFromView(target);
  return p;
}

class EvalFeatureBaseline : public ::testing::TestWithParam<std::string> {};

TEST_P(EvalFeatureBaseline, RegistersRedkitchen20To0AndIsDeterministic) {
  if (!fs::is_directory(testing::RedkitchenDir())) GTEST_SKIP() << "no ../shared data";
  const RealPair p = Redkitchen20To0();
  FeatureBaselineConfig c;
  c.detector = GetParam();
  c.seed = 3;
  const MethodOutput out = RunFeatureBaseline(c, p.source, p.target);
  EXPECT_TRUE(out.valid) << out.reason;
  EXPECT_EQ(out.path, GetParam());
  EXPECT_GE(out.num_inliers, c.min_inliers) << out.reason;
  EXPECT_LT(RotationErrorDeg(out.T_target_source, p.gt), 5.0) << out.reason;
  EXPECT_LT(TranslationErrorM(out.T_target_source, p.gt), 0.10) << out.reason;
  // Same input and seed, same transform, bit for bit.
  const MethodOutput again = RunFeatureBaseline(c, p.source, p.target);
  EXPECT_EQ(again.num_inliers, out.num_inliers);
  EXPECT_EQ(again.correspondences.size(), out.correspondences.size());
  EXPECT_TRUE(again.T_target_source == out.T_target_source);
}

INSTANTIATE_TEST_SUITE_P(Methods, EvalFeatureBaseline, ::testing::Values("sift", "orb"));

TEST(EvalFeatureBaselineVerdict, TooFewCorrespondencesIsInvalid) {
  // A textureless pair: no keypoints, so no correspondences and an invalid verdict.
  View v;
  v.color = cv::Mat(120, 160, CV_8UC3, cv::Scalar(128, 128, 128));
  v.depth = cv::Mat(120, 160, CV_32FC1, cv::Scalar(1.0f));
  v.intrinsics.fx = v.intrinsics.fy = 100;
  v.intrinsics.cx = 80;
  v.intrinsics.cy = 60;
  v.intrinsics.width = 160;
  v.intrinsics.height = 120;
  const Scan s = ScanFromView(v);
  FeatureBaselineConfig c;
  const MethodOutput out = RunFeatureBaseline(c, s, s);
  EXPECT_FALSE(out.valid);
  EXPECT_TRUE(out.correspondences.empty()) << out.reason;
  EXPECT_EQ(out.num_inliers, 0);
}

}  // namespace
}  // namespace zeroreg
