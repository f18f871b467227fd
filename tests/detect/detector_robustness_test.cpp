// Detector checks beyond detector_test.cpp: YOLOX on frame 500 (MANIFEST), truncated / corrupt
// Darknet files, bad images and config values, and the forward time (printed, not asserted).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "detect/perception_test_util.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using perception_test::ExpectInputError;
using perception_test::FramePath;
using perception_test::ModelPaths;
using perception_test::TempDir;
using perception_test::WriteText;

TEST(DetectorYolox, RedkitchenFrame500MatchesManifest) {
  const cv::Mat image = ReadColorImage(FramePath(500, "color.jpg"));
  const std::vector<Detection> dets =
      MakeDetector(DetectorConfig{}, ModelPaths())->Detect(image, "frame-000500.color.jpg");
  // MANIFEST: dining table 0.85, chair 0.84/0.79/0.67, cup 0.66/0.63, book 0.44/0.33.
  const std::vector<std::pair<std::string, float>> expected = {
      {"dining table", 0.85f}, {"chair", 0.84f}, {"chair", 0.79f}, {"chair", 0.67f},
      {"cup", 0.66f},          {"cup", 0.63f},   {"book", 0.44f},  {"book", 0.33f}};
  ASSERT_EQ(dets.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(dets[i].label, expected[i].first) << i;
    EXPECT_NEAR(dets[i].score, expected[i].second, 0.02) << i << " " << dets[i].label;
    EXPECT_GE(dets[i].box.x, 0.0f);
    EXPECT_GE(dets[i].box.y, 0.0f);
    EXPECT_LE(dets[i].box.br().x, 640.0f);
    EXPECT_LE(dets[i].box.br().y, 480.0f);
    EXPECT_GT(dets[i].box.area(), 100.0f);
  }
}

TEST(DetectorModels, TruncatedDarknetWeightsNamed) {
  // OpenCV's importer does not notice a short weights file; the detector must (it would otherwise
  // run with garbage parameters).
  TempDir dir("detect_truncated");
  DetectorConfig darknet;
  darknet.backend = "darknet";
  DetectorModelPaths paths = ModelPaths();
  std::ifstream in(paths.darknet_weights, std::ios::binary);
  std::string head(1000000, '\0');  // the real file is 3,693,964 bytes
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  ASSERT_TRUE(in.good());
  paths.darknet_weights = dir.File("truncated.weights");
  WriteText(paths.darknet_weights, head);
  ExpectInputError([&] { MakeDetector(darknet, paths); }, {"truncated.weights", "truncated"});
  // The intact file loads (the check does not reject good weights).
  EXPECT_NO_THROW(MakeDetector(darknet, ModelPaths()));
}

TEST(DetectorModels, CorruptCfgAndClassListNamed) {
  TempDir dir("detect_corrupt");
  DetectorConfig darknet;
  darknet.backend = "darknet";
  DetectorModelPaths paths = ModelPaths();
  paths.darknet_cfg = dir.File("garbage.cfg");
  WriteText(paths.darknet_cfg, "this is not a darknet cfg\n[[[\n");
  ExpectInputError([&] { MakeDetector(darknet, paths); }, {"garbage.cfg"});
  paths = ModelPaths();
  paths.darknet_cfg = dir.File("missing.cfg");
  ExpectInputError([&] { MakeDetector(darknet, paths); }, {"missing.cfg"});
  paths = ModelPaths();
  paths.yolox_classes = dir.File("empty_classes.txt");
  WriteText(paths.yolox_classes, "\n\n");
  ExpectInputError([&] { MakeDetector(DetectorConfig{}, paths); }, {"empty_classes.txt", "empty"});
}

TEST(DetectorModels, BadImageAndConfigNamed) {
  auto detector = MakeDetector(DetectorConfig{}, ModelPaths());
  ExpectInputError([&] { detector->Detect(cv::Mat(48, 64, CV_8UC1), "gray.png"); },
                   {"gray.png", "3-channel"});
  ExpectInputError([&] { detector->Detect(cv::Mat(), "empty.png"); }, {"empty.png"});
  DetectorConfig config;
  config.score_threshold = 1.5;
  ExpectInputError([&] { MakeDetector(config, ModelPaths()); }, {"detector.score_threshold"});
  config = DetectorConfig{};
  config.nms_iou = 0.0;
  ExpectInputError([&] { MakeDetector(config, ModelPaths()); }, {"detector.nms_iou"});
}

TEST(DetectorYolox, ThinImagesAreDetectedNotAnOpenCvAssertion) {
  // 1x1000 letterboxes to 0 x 416 pixels, which cv::resize refused (exit 3).
  auto detector = MakeDetector(DetectorConfig{}, ModelPaths());
  EXPECT_NO_THROW(detector->Detect(cv::Mat(1, 1000, CV_8UC3, cv::Scalar(90, 90, 90)), "thin.png"));
  EXPECT_NO_THROW(detector->Detect(cv::Mat(1000, 1, CV_8UC3, cv::Scalar(90, 90, 90)), "tall.png"));
}

TEST(DetectorTiming, ForwardPrinted) {
  // Informational (the 2 cores are shared; no assertion on time): median wall and thread-CPU time
  // of Detect() on frame 0 over 7 runs after a warm-up, per backend.
  const cv::Mat image = ReadColorImage(FramePath(0, "color.jpg"));
  for (const char* backend : {"yolox", "darknet", "picodet", "ensemble"}) {
    DetectorConfig config;
    config.backend = backend;
    auto detector = MakeDetector(config, ModelPaths());
    const size_t expected = detector->Detect(image, "frame-000000.color.jpg").size();
    std::vector<double> wall, cpu;
    for (int run = 0; run < 7; ++run) {
      const double c0 = perception_test::ThreadCpuMs();
      const auto t0 = std::chrono::steady_clock::now();
      const std::vector<Detection> dets = detector->Detect(image, "frame-000000.color.jpg");
      wall.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      cpu.push_back(perception_test::ThreadCpuMs() - c0);
      ASSERT_EQ(dets.size(), expected);  // same answer every run
    }
    std::printf("[ detect   ] %s on a 640x480 frame: median %.1f ms wall, %.1f ms thread CPU\n",
                backend, perception_test::Median(wall), perception_test::Median(cpu));
  }
}

}  // namespace
}  // namespace zeroreg
