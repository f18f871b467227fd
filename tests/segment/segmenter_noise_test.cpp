// The segmenter's noise floor (SegmenterConfig::depth_noise_sigmas): on noisy depth the depth
// steps keep the object instead of calling its noise "edges"; real depth edges still cut it; on
// Kinect v1 frames the masks are what they were without the floor.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>
#include <string>

#include "detect/perception_test_util.hpp"
#include "estimate/depth_noise.hpp"
#include "noisy_wall.hpp"
#include "segment/segmenter.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing::NoisyWall;

// The box standing in front of the wall of NoisyWall (x 251..399, y 201..479), and a detection
// box around it with a margin of wall.
const cv::Rect kObject(251, 201, 149, 279);

Detection BoxAroundObject() {
  Detection d;
  d.box = cv::Rect2f(236.0f, 186.0f, 179.0f, 294.0f);
  d.label = "box";
  d.score = 1.0f;
  return d;
}

double Iou(const cv::Mat& a, const cv::Mat& b) {
  const int u = cv::countNonZero(a | b);
  return u == 0 ? 1.0 : static_cast<double>(cv::countNonZero(a & b)) / u;
}

double ObjectCovered(const cv::Mat& mask) {
  return static_cast<double>(cv::countNonZero(mask(kObject))) / kObject.area();
}

// Depth with 10 mm at 1 m (sigma 2.3 cm on the object at 1.5 m): without the floor
// the 7x7 depth-edge windows see noise spreads of ~10 cm, over 5 % of the depth, and the mask
// loses the object; with the view's measured noise it is the mask of the same scene without
// noise (IoU > 0.9), so the object's real edges (0.5 m in front of the wall) still bound it.
TEST(SegmenterDepthNoise, NoisyDepthGivesTheQuietMask) {
  const View noisy = NoisyWall(0.01, 21), quiet = NoisyWall(0.0, 21);
  const double a = *MeasureDepthNoiseAt1m(noisy);
  ASSERT_NEAR(a, 0.01, 0.001);
  for (const std::string backend : {"depth", "depth-grabcut", "grabcut-depth"}) {
    SCOPED_TRACE(backend);
    SegmenterConfig config;
    config.backend = backend;
    auto segmenter = MakeSegmenter(config);
    const Detection box = BoxAroundObject();
    const cv::Mat reference =
        segmenter->Segment(quiet.color, quiet.depth, box, 0, "wall", kUnknownDepthNoise);
    const cv::Mat without =
        segmenter->Segment(noisy.color, noisy.depth, box, 0, "wall", kUnknownDepthNoise);
    const cv::Mat with = segmenter->Segment(noisy.color, noisy.depth, box, 0, "wall", a);
    EXPECT_GT(ObjectCovered(reference), 0.9);
    EXPECT_LT(ObjectCovered(without), 0.1);
    EXPECT_GT(Iou(with, reference), 0.9);
  }
  // The floor is a setting: 0 turns it off.
  SegmenterConfig off;
  off.backend = "depth";
  off.depth_noise_sigmas = 0.0;
  const cv::Mat mask =
      MakeSegmenter(off)->Segment(noisy.color, noisy.depth, BoxAroundObject(), 0, "wall", a);
  EXPECT_LT(ObjectCovered(mask), 0.1);
}

// Noise-free depth measures a ~ 0; even with a = 1.5 mm (Kinect-like) the floors stay below the
// relative thresholds at these depths (1.35-2.2 m), so the mask is bit-identical to the one
// without a noise floor.
TEST(SegmenterDepthNoise, QuietDepthGivesTheSameMask) {
  const View view = NoisyWall(0.0, 21);
  SegmenterConfig config;
  config.backend = "depth";
  auto segmenter = MakeSegmenter(config);
  const cv::Mat without =
      segmenter->Segment(view.color, view.depth, BoxAroundObject(), 0, "wall", kUnknownDepthNoise);
  const cv::Mat with =
      segmenter->Segment(view.color, view.depth, BoxAroundObject(), 0, "wall", 0.0015);
  EXPECT_EQ(cv::countNonZero(without != with), 0);
  EXPECT_GT(ObjectCovered(with), 0.9);
}

// The edge mask: noise alone makes no edge with the floor; a real jump does.
TEST(SegmenterDepthNoise, EdgeMaskFloor) {
  const View view = NoisyWall(0.01, 5);
  const double a = 0.01, sigmas = SegmenterConfig().depth_noise_sigmas;
  const cv::Mat plain = detail::DepthEdgeMask(view.depth, 3, 0.05);
  const cv::Mat floored = detail::DepthEdgeMask(view.depth, 3, 0.05, 2.0 * sigmas * a);
  // The far half of the wall (2.1-3 m), away from the object: noise only.
  const cv::Rect far_wall(450, 10, 180, 460);
  EXPECT_GT(cv::countNonZero(plain(far_wall)), far_wall.area() / 2);
  EXPECT_LT(cv::countNonZero(floored(far_wall)), far_wall.area() / 1000);
  // The object's left and right edges (0.5 m jumps) stay edges on every row.
  for (int y = 210; y < 470; y += 10) {
    EXPECT_EQ(floored.at<uchar>(y, 250), 255) << y;
    EXPECT_EQ(floored.at<uchar>(y, 399), 255) << y;
  }
}

// The band's floor alone: a flat patch 3 m away with 10 mm at 1 m (sigma 9 cm) and no size term.
// The band max(5 cm, 3 % of 3 m) = 9 cm keeps one sigma, about two thirds of the readings; with
// the floor (4 sigma = 36 cm) all but a few in ten thousand.
TEST(SegmenterDepthNoise, DepthBandFloor) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.09f);
  cv::Mat depth(100, 100, CV_32FC1);
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) depth.at<float>(y, x) = 3.0f + noise(rng);
  }
  const cv::Mat none = cv::Mat::zeros(depth.size(), CV_8UC1);
  const cv::Mat all(depth.size(), CV_8UC1, cv::Scalar(255));
  SegmenterConfig config;
  config.erosion_px = 0;  // the band alone
  const auto kept = [&](double a) {
    const cv::Mat layer = detail::DepthLayer(depth, none, all, all, 0.0, config, a);
    return static_cast<double>(cv::countNonZero(layer)) / depth.total();
  };
  EXPECT_LT(kept(kUnknownDepthNoise), 0.75);
  EXPECT_GT(kept(0.01), 0.999);
}

// Kinect v1 frames (a ~1.7 mm): the edge floor passes the relative threshold only beyond ~3.6 m,
// so the masks of the frames' YOLOX boxes are the same with the measured noise as without it.
TEST(SegmenterDepthNoise, KinectMasksAsBefore) {
  auto detector = MakeDetector(DetectorConfig{}, perception_test::ModelPaths());
  auto segmenter = MakeSegmenter(SegmenterConfig{});
  int compared = 0;
  for (const int id : {0, 500}) {
    const std::string name = perception_test::FramePath(id, "color.jpg");
    const cv::Mat bgr = ReadColorImage(name);
    const cv::Mat depth = ReadDepthImage(perception_test::FramePath(id, "depth.png"), 1000.0);
    View view;
    view.depth = depth;
    const double a = *MeasureDepthNoiseAt1m(view);
    ASSERT_GT(a, 0.001);
    const std::vector<Detection> detections = detector->Detect(bgr, name);
    const ViewMasks without =
        segmenter->SegmentView(bgr, depth, detections, name, kUnknownDepthNoise);
    const ViewMasks with = segmenter->SegmentView(bgr, depth, detections, name, a);
    ASSERT_EQ(without.masks.size(), with.masks.size());
    for (size_t i = 0; i < with.masks.size(); ++i) {
      EXPECT_EQ(cv::countNonZero(without.masks[i] != with.masks[i]), 0) << id << " #" << i;
      ++compared;
    }
  }
  EXPECT_GE(compared, 8);
}

}  // namespace
}  // namespace zeroreg
