// The mirror-image rule (src/pipeline/handedness.hpp) on stand-in counts and a stand-in feature
// extractor. The real mirrored frames: python/tests/test_mirrored_scan.py and
// scripts/bench-mirrored.py.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <vector>

#include "pipeline/handedness.hpp"

namespace zeroreg {
namespace {

TEST(Handedness, AMirrorImageSharesManyMoreMatchesFlipped) {
  const VerifyConfig config;  // mirror_min_matches 20, mirror_ratio 2.5
  // Measured on flipped frames (flipped, as given): the TUM cabinet's near-symmetric texture is the
  // closest, every one a mirror image.
  for (const Handedness h : {Handedness{12, 41}, Handedness{22, 113}, Handedness{5, 72},
                             Handedness{0, 442}, Handedness{3, 20}}) {
    EXPECT_TRUE(LooksMirrored(h, config)) << h.as_given << " " << h.mirrored;
  }
  // Right results of the lists: the most flipped matches, and the highest ratio with 10 or more.
  for (const Handedness h : {Handedness{108, 35}, Handedness{7, 13}, Handedness{15, 21},
                             Handedness{0, 3}, Handedness{0, 19}}) {
    EXPECT_FALSE(LooksMirrored(h, config)) << h.as_given << " " << h.mirrored;
  }
  // The threshold: the larger of the floor and the ratio times the matches as given.
  EXPECT_EQ(MirrorThreshold({4, 0}, config), 20.0);
  EXPECT_EQ(MirrorThreshold({12, 0}, config), 30.0);
  EXPECT_FALSE(LooksMirrored({12, 29}, config));
  EXPECT_TRUE(LooksMirrored({12, 30}, config));
  // 0 turns the test off.
  VerifyConfig off = config;
  off.mirror_min_matches = 0;
  EXPECT_FALSE(LooksMirrored({0, 442}, off));
}

// Returns one keypoint at a fixed pixel of whatever image it is given, with a descriptor made from
// the colour there: what the mirrored extraction must map back to the view's own pixels.
class OnePointExtractor : public FeatureExtractor {
 public:
  std::string name() const override { return "one point"; }
  ImageFeatures Extract(const cv::Mat& bgr) const override {
    ImageFeatures f;
    f.keypoints.emplace_back(10.0f, 5.0f);
    f.scores.push_back(1.0f);
    const cv::Vec3b c = bgr.at<cv::Vec3b>(5, 10);
    f.descriptors = Eigen::MatrixXf(1, 3);
    f.descriptors << c[0], c[1], c[2];
    f.descriptors.row(0).normalize();
    return f;
  }
};

TEST(Handedness, MirroredFeaturesAreInTheViewsOwnPixels) {
  View view;
  view.intrinsics = {50.0, 50.0, 19.5, 9.5, 40, 20};
  view.color = cv::Mat(20, 40, CV_8UC3, cv::Scalar(0, 0, 0));
  view.depth = cv::Mat(20, 40, CV_32FC1, cv::Scalar(2.0f));
  // The flipped image's pixel (10, 5) shows the view's pixel (29, 5): coloured so the descriptor
  // tells which pixel was read.
  view.color.at<cv::Vec3b>(5, 29) = cv::Vec3b(0, 255, 0);
  Scan scan;
  scan.views.push_back(view);
  const std::vector<LiftedFeatures> f =
      ExtractMirroredFeatures(OnePointExtractor(), scan, {ViewLift()});
  ASSERT_EQ(f.size(), 1u);
  ASSERT_EQ(f[0].features.size(), 1);
  EXPECT_FLOAT_EQ(f[0].features.keypoints[0].x(), 29.0f);
  EXPECT_FLOAT_EQ(f[0].features.keypoints[0].y(), 5.0f);
  EXPECT_FLOAT_EQ(f[0].features.descriptors(0, 1), 1.0f);  // green: the flipped image was read
  ASSERT_EQ(f[0].points.size(), 1u);
  // Lifted at the view's pixel (29, 5): x = (29 - 19.5) * 2 / 50.
  EXPECT_NEAR(f[0].points[0].x(), 0.38, 1e-6);
  EXPECT_NEAR(f[0].points[0].z(), 2.0, 1e-6);
}

}  // namespace
}  // namespace zeroreg
