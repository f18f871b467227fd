// XFeat at the image's own size: the input size rule, the rewritten any-size model
// (scripts/rewrite_onnx_xfeat.py) computing what the 640x640 export computes on a 640x640 input,
// and the keypoints of real frames at their own size against the padded square's, with the
// square's contrast (the default) and with upstream's normalisation.
#include "features/xfeat_extractor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "detect/perception_test_util.hpp"
#include "test_paths.hpp"

namespace zeroreg {
namespace {

using perception_test::AssetsDir;

InferenceConfig OnnxRuntime() {
  InferenceConfig c;
  c.engine = "onnxruntime";
  c.graph_cache = "off";
  return c;
}

XFeatExtractor Make(const XFeatInput& input, const InferenceConfig& inference) {
  return XFeatExtractor(AssetsDir() + "/" + XFeatExtractor::ModelFile(inference, input),
                        FeatureConfig(), inference, input);
}

cv::Mat ReadColor(const std::string& path) {
  cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_FALSE(img.empty()) << path;
  return img;
}

TEST(XFeat, InputSizeFollowsTheImage) {
  const auto own = [](int w, int h) { return XFeatExtractor::InputSize({w, h}, false); };
  EXPECT_EQ(own(640, 480), cv::Size(640, 480));   // 7-Scenes, TUM: no scaling, no fill
  EXPECT_EQ(own(540, 360), cv::Size(640, 448));   // HoloLens: 640 x 426.7, 21 rows of fill
  EXPECT_EQ(own(480, 640), cv::Size(480, 640));   // portrait
  EXPECT_EQ(own(1280, 720), cv::Size(640, 384));  // scaled down by 2, 360 -> 384
  EXPECT_EQ(own(320, 240), cv::Size(640, 480));   // scaled up by 2
  EXPECT_EQ(own(1000, 1000), cv::Size(640, 640));
  EXPECT_EQ(XFeatExtractor::InputSize({640, 480}, true), cv::Size(640, 640));
}

TEST(XFeat, OpenCvDnnKeepsTheSquareExport) {
  InferenceConfig opencv;
  opencv.engine = "opencv";
  EXPECT_TRUE(XFeatExtractor::UsesSquareInput(opencv));
  EXPECT_EQ(XFeatExtractor::ModelFile(opencv), "xfeat/xfeat_640x640.onnx");
  if (!OnnxRuntimeAvailable()) return;
  EXPECT_EQ(XFeatExtractor::ModelFile(OnnxRuntime()), "xfeat/xfeat_any_size.onnx");
  XFeatInput square;
  square.square = true;
  EXPECT_EQ(XFeatExtractor::ModelFile(OnnxRuntime(), square), "xfeat/xfeat_640x640.onnx");
}

// On a 640x640 image both models get the same input (no fill), so the rewrite must give the same
// keypoints, scores and descriptors up to the rounding of kernels chosen for other shapes: it only
// replaced the traced unfold by SpaceToDepth and the constant Resize sizes by the map's own size.
// (The order of keypoints with nearly equal scores may differ, so they are compared by position.)
TEST(XFeat, AnySizeModelComputesTheSquareExportOn640x640) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  XFeatInput square_input;
  square_input.square = true;
  const XFeatExtractor square = Make(square_input, OnnxRuntime());
  const XFeatExtractor any_size = Make(XFeatInput{}, OnnxRuntime());
  for (int frame : {0, 500}) {
    cv::Mat img;
    cv::resize(ReadColor(perception_test::FramePath(frame, "color.jpg")), img, {640, 640});
    const ImageFeatures a = square.Extract(img), b = any_size.Extract(img);
    ASSERT_GT(a.keypoints.size(), 1000u);
    ASSERT_EQ(a.keypoints.size(), b.keypoints.size()) << "frame " << frame;
    std::map<std::pair<float, float>, size_t> at;
    for (size_t j = 0; j < b.keypoints.size(); ++j)
      at[{b.keypoints[j].x(), b.keypoints[j].y()}] = j;
    int same = 0;
    double max_score_gap = 0, max_descriptor_gap = 0;
    for (size_t i = 0; i < a.keypoints.size(); ++i) {
      const auto it = at.find({a.keypoints[i].x(), a.keypoints[i].y()});
      if (it == at.end()) continue;
      ++same;
      max_score_gap = std::max(max_score_gap, std::abs(double{a.scores[i]} - b.scores[it->second]));
      max_descriptor_gap =
          std::max(max_descriptor_gap,
                   static_cast<double>((a.descriptors.row(static_cast<Eigen::Index>(i)) -
                                        b.descriptors.row(static_cast<Eigen::Index>(it->second)))
                                           .cwiseAbs()
                                           .maxCoeff()));
    }
    std::printf(
        "frame %d at 640x640: %d of %zu keypoints at the same position, score gap %.2g, "
        "descriptor gap %.2g\n",
        frame, same, a.keypoints.size(), max_score_gap, max_descriptor_gap);
    // The top-k cut may exchange a few keypoints of equal score at its end.
    EXPECT_GE(same, static_cast<int>(a.keypoints.size()) - 5) << "frame " << frame;
    EXPECT_LE(max_score_gap, 1e-5) << "frame " << frame;
    EXPECT_LE(max_descriptor_gap, 1e-4) << "frame " << frame;
  }
}

// At the image's own size the network sees no fill. With the square's contrast (the default) the
// normalised image is the square's inside the image, and only the last rows (whose receptive
// fields reached into the fill) differ; with upstream's own normalisation (contrast 1) the
// keypoint scores change a little everywhere. Checked on a 640x480 7-Scenes frame (no fill at
// all now) and a 540x360 HoloLens frame (640x448 instead of 640x640).
struct Overlap {
  double same_fraction = 0.0;  // own-size keypoints with a square keypoint within 0.5 px
  double median_cosine = 0.0;  // of those pairs' descriptors
};
Overlap CompareWithSquare(const cv::Mat& img, const ImageFeatures& a, const ImageFeatures& b) {
  int same = 0;
  std::vector<double> cosines;
  for (size_t i = 0; i < b.keypoints.size(); ++i) {
    for (size_t j = 0; j < a.keypoints.size(); ++j) {
      if ((b.keypoints[i] - a.keypoints[j]).squaredNorm() <= 0.25f) {
        ++same;
        cosines.push_back(b.descriptors.row(static_cast<Eigen::Index>(i))
                              .dot(a.descriptors.row(static_cast<Eigen::Index>(j))));
        break;
      }
    }
    // Every keypoint lies inside the image.
    EXPECT_GE(b.keypoints[i].x(), -0.5f);
    EXPECT_GE(b.keypoints[i].y(), -0.5f);
    EXPECT_LE(b.keypoints[i].x(), img.cols - 0.5f);
    EXPECT_LE(b.keypoints[i].y(), img.rows - 0.5f);
  }
  std::sort(cosines.begin(), cosines.end());
  Overlap out;
  out.same_fraction = b.keypoints.empty() ? 0.0 : static_cast<double>(same) / b.keypoints.size();
  out.median_cosine = cosines.empty() ? 0.0 : cosines[cosines.size() / 2];
  return out;
}

TEST(XFeat, OwnSizeKeypointsAreTheSquareInputsKeypoints) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  XFeatInput square_input;
  square_input.square = true;
  XFeatInput upstream_input;
  upstream_input.square_contrast = false;
  const XFeatExtractor square = Make(square_input, OnnxRuntime());
  const XFeatExtractor own = Make(XFeatInput{}, OnnxRuntime());
  const XFeatExtractor upstream = Make(upstream_input, OnnxRuntime());
  for (const std::string& path :
       {perception_test::FramePath(0, "color.jpg"),
        testing::SharedDir() + "/data/hololens-office/frames/frame-000003.color.jpg"}) {
    const cv::Mat img = ReadColor(path);
    const ImageFeatures a = square.Extract(img), b = own.Extract(img), c = upstream.Extract(img);
    ASSERT_GT(a.keypoints.size(), 500u) << path;
    const Overlap with_contrast = CompareWithSquare(img, a, b);
    const Overlap without = CompareWithSquare(img, a, c);
    std::printf(
        "%s: square %zu keypoints; own size %zu, %.1f%% the same, median cosine %.5f; "
        "upstream normalisation %zu, %.1f%% the same, median cosine %.5f\n",
        path.c_str(), a.keypoints.size(), b.keypoints.size(), 100 * with_contrast.same_fraction,
        with_contrast.median_cosine, c.keypoints.size(), 100 * without.same_fraction,
        without.median_cosine);
    EXPECT_NEAR(static_cast<double>(b.keypoints.size()), static_cast<double>(a.keypoints.size()),
                0.02 * a.keypoints.size())
        << path;
    EXPECT_GE(with_contrast.same_fraction, 0.95) << path;
    EXPECT_GE(with_contrast.median_cosine, 0.99999) << path;
    EXPECT_GE(without.same_fraction, 0.7) << path;
    EXPECT_GE(without.median_cosine, 0.98) << path;
  }
}

// Images of other sizes go through the same rule: a 1280x960 copy of a 640x480 frame is scaled back
// to 640x480 inside, and its keypoints, mapped back to its own pixels, are the frame's keypoints
// at twice the coordinates; a 600x400 crop runs at 640x448 (scaled 1.067, 21 rows of fill) and
// keeps every keypoint inside the crop.
TEST(XFeat, KeypointsMapBackToTheImagesOwnPixels) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  const XFeatExtractor xfeat = Make(XFeatInput{}, OnnxRuntime());
  const cv::Mat frame = ReadColor(perception_test::FramePath(0, "color.jpg"));
  cv::Mat large;
  cv::resize(frame, large, {1280, 960}, 0, 0, cv::INTER_LINEAR);
  const ImageFeatures a = xfeat.Extract(frame), b = xfeat.Extract(large);
  ASSERT_GT(a.keypoints.size(), 1000u);
  int near = 0;
  for (const Eigen::Vector2f& k : b.keypoints) {
    const Eigen::Vector2f back =
        (k + Eigen::Vector2f(0.5f, 0.5f)) / 2 - Eigen::Vector2f(0.5f, 0.5f);
    for (const Eigen::Vector2f& j : a.keypoints) {
      if ((back - j).squaredNorm() <= 1.0f) {
        ++near;
        break;
      }
    }
  }
  std::printf("1280x960 copy: %zu keypoints, %d within 1 px of the 640x480 frame's\n",
              b.keypoints.size(), near);
  EXPECT_GE(near, static_cast<int>(0.7 * b.keypoints.size()));  // 82 % here

  const cv::Mat crop = frame(cv::Rect(20, 40, 600, 400)).clone();
  EXPECT_EQ(XFeatExtractor::InputSize(crop.size(), false), cv::Size(640, 448));
  const ImageFeatures c = xfeat.Extract(crop);
  ASSERT_GT(c.keypoints.size(), 1000u);
  for (const Eigen::Vector2f& k : c.keypoints) {
    EXPECT_GE(k.x(), -0.5f);
    EXPECT_GE(k.y(), -0.5f);
    EXPECT_LE(k.x(), crop.cols - 0.5f);
    EXPECT_LE(k.y(), crop.rows - 0.5f);
  }
}

}  // namespace
}  // namespace zeroreg
