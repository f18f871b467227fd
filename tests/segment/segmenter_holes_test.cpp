// Thin holes are not depth edges (SegmenterConfig::min_hole_width_px): a gap of missing readings
// narrower than the width is a hole in the sensor's sampling, not a surface boundary, so the
// segmenter measures the depth jump across it; a wide hole (a shadow, an out-of-range surface)
// still makes an edge. HoloLens depth has such gaps all over the image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "segment/mask_stats.hpp"
#include "segment/segmenter.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using mask_test::DepthIqr;

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

// Even widths are exact too: with 2, a 2 px gap is a hole whose both sides are edges alike, and a
// 1 px gap is not.
TEST(SegmenterHoles, EvenWidthIsSymmetric) {
  const cv::Mat depth = FlatWithHoles();  // 1 px gap at x = 40, 2 px gap at x = 80..81
  const cv::Mat edges = detail::DepthEdgeMask(depth, kRadius, kRelative, 0.0, 2);
  for (int d = 1; d <= kRadius; ++d) {
    SCOPED_TRACE(d);
    EXPECT_EQ(edges.at<uchar>(70, 80 - d), 255);
    EXPECT_EQ(edges.at<uchar>(70, 81 + d), 255);
    EXPECT_EQ(edges.at<uchar>(70, 40 - d), 0);
    EXPECT_EQ(edges.at<uchar>(70, 40 + d), 0);
  }
  EXPECT_EQ(edges.at<uchar>(70, 80 - kRadius - 1), 0);
  EXPECT_EQ(edges.at<uchar>(70, 81 + kRadius + 1), 0);
}

// The segmenter works on each box padded by the radius and the hole width: its edges are the
// whole image's, cropped, also where a wide hole lies just outside the box.
TEST(SegmenterHoles, BoxEdgesEqualTheWholeImages) {
  const cv::Mat depth = ReadDepthImage(
      testing::SharedDir() + "/data/hololens-office/frames/frame-000041.depth.png", 1000.0);
  const std::vector<cv::Rect> boxes = {{330, 99, 205, 198}, {0, 0, 60, 40},   {500, 300, 40, 60},
                                       {218, 1, 86, 80},    {100, 150, 7, 9}, {10, 200, 300, 3}};
  for (const int width : {1, 2, 3, 5}) {
    SegmenterConfig config;
    config.min_hole_width_px = width;
    const cv::Mat whole = detail::DepthEdgeMask(depth, config.depth_edge_radius_px,
                                                DepthModel().edge_relative, 0.0, width);
    for (const cv::Rect& box : boxes) {
      SCOPED_TRACE("width " + std::to_string(width) + " box " + std::to_string(box.x) + "," +
                   std::to_string(box.y));
      const cv::Mat in_box =
          detail::BoxDepthEdges(depth, box, config, DepthModel().edge_relative, 0.0);
      EXPECT_EQ(cv::countNonZero(in_box != whole(box)), 0);
    }
  }
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
    EXPECT_LT(old - thin, 0.03);
  }
}

// A HoloLens box around the couch of frame 41 (the detector's box): the mask keeps several
// times the pixels it kept when every gap was an edge, and its depth spreads less than the box's
// (the floor and the wall behind stay out).
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
  const cv::Mat box = cv::Mat::zeros(depth.size(), CV_8UC1);
  box(detail::BoxPixelRect(couch.box, depth.size())).setTo(255);
  const double mask_iqr = DepthIqr(depth, now), box_iqr = DepthIqr(depth, box);
  std::printf("[ holes    ] depth interquartile range: mask %.3f m, box %.3f m\n", mask_iqr,
              box_iqr);
  EXPECT_LT(mask_iqr, box_iqr);
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
