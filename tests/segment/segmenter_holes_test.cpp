// Thin holes are not depth edges (SegmenterConfig::min_hole_width_px): a gap of missing readings
// narrower than the width is a hole in the sensor's sampling, not a surface boundary, so the
// segmenter measures the depth jump across it; a wide hole (a shadow, an out-of-range surface)
// still makes an edge. HoloLens depth has such gaps all over the image.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "segment/segmenter.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

constexpr int kRadius = 3;
constexpr double kRelative = 0.05;

// Share of the valid pixels of `depth` that the edge mask marks.
double EdgeShare(const cv::Mat& depth, int min_hole_width_px) {
  const cv::Mat edges = detail::DepthEdgeMask(depth, kRadius, kRelative, 0.0, min_hole_width_px);
  return static_cast<double>(cv::countNonZero(edges)) / cv::countNonZero(depth > 0.0f);
}

// A flat surface 2 m away with a vertical gap of 1 px at x = 40, one of 2 px at x = 80..81 and a
// 6 x 6 px hole at (120..125, 40..45).
cv::Mat FlatWithHoles() {
  cv::Mat depth(100, 200, CV_32FC1, cv::Scalar(2.0f));
  depth.col(40).setTo(0.0f);
  depth.colRange(80, 82).setTo(0.0f);
  depth(cv::Rect(120, 40, 6, 6)).setTo(0.0f);
  return depth;
}

TEST(SegmenterHoles, ThinGapsAreNotEdgesWideHolesAre) {
  const cv::Mat depth = FlatWithHoles();
  const cv::Mat thin_rule = detail::DepthEdgeMask(depth, kRadius, kRelative, 0.0, 3);
  const cv::Mat every_hole = detail::DepthEdgeMask(depth, kRadius, kRelative, 0.0, 1);
  for (const int x : {37, 39, 41, 43, 77, 79, 82, 84}) {
    SCOPED_TRACE(x);
    EXPECT_EQ(thin_rule.at<uchar>(70, x), 0);     // beside a 1 or 2 px gap: one surface
    EXPECT_EQ(every_hole.at<uchar>(70, x), 255);  // the old rule: an edge
  }
  // Around the 6 x 6 hole both rules mark the pixels within the radius, and none further out.
  for (const auto& mask : {thin_rule, every_hole}) {
    EXPECT_EQ(mask.at<uchar>(42, 119), 255);
    EXPECT_EQ(mask.at<uchar>(42, 128), 255);
    EXPECT_EQ(mask.at<uchar>(37, 122), 255);
    EXPECT_EQ(mask.at<uchar>(42, 130), 0);
    EXPECT_EQ(mask.at<uchar>(42, 115), 0);
  }
  // No pixel of the flat surface away from the wide hole is an edge under the new rule.
  EXPECT_EQ(cv::countNonZero(thin_rule(cv::Rect(0, 60, 200, 40))), 0);
}

// A real jump across a thin gap stays an edge: the window's valid readings on either side differ.
TEST(SegmenterHoles, JumpAcrossAThinGapIsStillAnEdge) {
  cv::Mat depth(60, 100, CV_32FC1, cv::Scalar(2.0f));
  depth.colRange(51, 100).setTo(1.5f);  // 0.5 m nearer right of the gap
  depth.col(50).setTo(0.0f);
  const cv::Mat edges = detail::DepthEdgeMask(depth, kRadius, kRelative, 0.0, 3);
  for (int y = 5; y < 55; y += 5) {
    EXPECT_EQ(edges.at<uchar>(y, 48), 255) << y;
    EXPECT_EQ(edges.at<uchar>(y, 52), 255) << y;
    EXPECT_EQ(edges.at<uchar>(y, 40), 0) << y;
    EXPECT_EQ(edges.at<uchar>(y, 60), 0) << y;
  }
}

// The real frames: on HoloLens depth (rings of 1-2 px gaps) the old rule marked most valid pixels
// as edges and the new one about a tenth; on Kinect v1 and TUM frames, whose holes are nearly all
// wide, the two rules differ on a few percent of the pixels.
TEST(SegmenterHoles, RealFramesPerSensor) {
  struct Frame {
    std::string path;
    double max_share_thin_rule, min_share_old_rule;
  };
  const std::string data = testing::SharedDir() + "/data/";
  for (const Frame& f : {Frame{data + "hololens-office/frames/frame-000041.depth.png", 0.2, 0.6},
                         Frame{data + "hololens-office/frames/frame-000068.depth.png", 0.2, 0.6}}) {
    SCOPED_TRACE(f.path);
    const cv::Mat depth = ReadDepthImage(f.path, 1000.0);
    const double thin = EdgeShare(depth, 3), old = EdgeShare(depth, 1);
    std::printf("[ holes    ] %s: edges on %.3f of the valid pixels (old rule %.3f)\n",
                f.path.c_str(), thin, old);
    EXPECT_LT(thin, f.max_share_thin_rule);
    EXPECT_GT(old, f.min_share_old_rule);
  }
  for (const std::string& path : {data + "7scenes-redkitchen/frames/frame-000000.depth.png",
                                  data + "7scenes-redkitchen/frames/frame-000500.depth.png",
                                  data + "tum-fr3-cabinet/frames/frame-000030.depth.png"}) {
    SCOPED_TRACE(path);
    const cv::Mat depth = ReadDepthImage(path, 1000.0);  // every folder in ../shared: mm
    const double thin = EdgeShare(depth, 3), old = EdgeShare(depth, 1);
    std::printf("[ holes    ] %s: edges on %.3f of the valid pixels (old rule %.3f)\n",
                path.c_str(), thin, old);
    EXPECT_LE(thin, old);
    EXPECT_LT(old - thin, 0.03);
  }
}

// A HoloLens box around the couch of frame 41 (the detector's box): the mask keeps several
// times the pixels it kept when every gap was an edge, and stays on one depth layer.
TEST(SegmenterHoles, HololensCouchMask) {
  const std::string frame = testing::SharedDir() + "/data/hololens-office/frames/frame-000041";
  const cv::Mat bgr = ReadColorImage(frame + ".color.jpg");
  const cv::Mat depth = ReadDepthImage(frame + ".depth.png", 1000.0);
  Detection couch;
  couch.box = cv::Rect2f(329.7f, 99.3f, 205.1f, 198.1f);
  couch.label = "couch";
  couch.score = 1.0f;
  SegmenterConfig config;
  config.backend = "depth";
  const cv::Mat now = MakeSegmenter(config)->Segment(bgr, depth, couch, 0, "41", 0.0);
  config.min_hole_width_px = 1;
  const cv::Mat before = MakeSegmenter(config)->Segment(bgr, depth, couch, 0, "41", 0.0);
  const int kept_now = cv::countNonZero(now), kept_before = cv::countNonZero(before);
  std::printf(
      "[ holes    ] couch of HoloLens frame 41: %d mask pixels (%d with every gap an edge)\n",
      kept_now, kept_before);
  EXPECT_GT(kept_now, 2 * kept_before);
  EXPECT_EQ(cv::countNonZero(now & (depth <= 0.0f)), 0);  // only pixels with depth
}

TEST(SegmenterHoles, WidthIsChecked) {
  SegmenterConfig config;
  config.min_hole_width_px = 0;
  try {
    MakeSegmenter(config);
    FAIL() << "min_hole_width_px 0 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("segmenter.min_hole_width_px"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace zeroreg
