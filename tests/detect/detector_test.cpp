// Detection backends (paper §3.2): YOLOX-Nano and Yolo-Fastest against the labels and scores the
// model MANIFESTs report on 7-Scenes redkitchen frames, and the precomputed-JSON reader.
#include "detect/detector.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <set>

#include "detect/backends.hpp"
#include "detect/perception_test_util.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using perception_test::ExpectInputError;
using perception_test::IoU;
using perception_test::ModelPaths;
using perception_test::ReadFrame;
using perception_test::TempDir;
using perception_test::WriteText;

TEST(DetectHelpers, LetterboxIsTopLeftOn114) {
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(10, 20, 30));
  double r = 0;
  cv::Mat canvas = detail::LetterboxTopLeft(img, 416, &r);
  EXPECT_DOUBLE_EQ(r, 0.65);
  ASSERT_EQ(canvas.size(), cv::Size(416, 416));
  EXPECT_EQ(canvas.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(canvas.at<cv::Vec3b>(311, 415), cv::Vec3b(10, 20, 30));  // 480 * 0.65 = 312 rows
  EXPECT_EQ(canvas.at<cv::Vec3b>(312, 0), cv::Vec3b(114, 114, 114));
}

TEST(DetectHelpers, NmsIsPerClass) {
  std::vector<Detection> c = {{{0, 0, 10, 10}, "a", 0.5f, 0},
                              {{1, 0, 10, 10}, "a", 0.9f, 0},  // IoU 0.82 with the first
                              {{1, 0, 10, 10}, "b", 0.6f, 1},  // same box, other class
                              {{30, 30, 10, 10}, "a", 0.4f, 0}};
  auto kept = detail::NonMaxSuppressionPerClass(c, 0.45);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_FLOAT_EQ(kept[0].score, 0.9f);
  EXPECT_EQ(kept[1].label, "b");
  EXPECT_FLOAT_EQ(kept[2].score, 0.4f);
}

TEST(DetectHelpers, ImageStem) {
  EXPECT_EQ(detail::ImageStem("a/b/frame-000000.color.jpg"), "frame-000000.color");
  EXPECT_EQ(detail::ImageStem("img.png"), "img");
  EXPECT_EQ(detail::ImageStem("noext"), "noext");
}

// MANIFEST (yolox_nano_coco): frame 000000 -> dining table 0.84, chair 0.74, cup 0.67, chair 0.53.
// Reference boxes were checked by drawing them on the frame (table, the chair behind the table, the
// white mug on the table, the chair on the left).
TEST(DetectYolox, RedkitchenFrame0MatchesManifest) {
  DetectorConfig yolox;
  yolox.backend = "yolox";
  auto det = MakeDetector(yolox, ModelPaths());
  EXPECT_EQ(det->name(), "yolox");
  const auto dets = det->Detect(ReadFrame(0), "frame-000000.color.jpg");
  struct Expected {
    std::string label;
    float score;
    cv::Rect2f box;
  };
  const std::vector<Expected> expected = {{"dining table", 0.84f, {203, 152, 435, 328}},
                                          {"chair", 0.74f, {420, 143, 130, 67}},
                                          {"cup", 0.67f, {367, 164, 36, 38}},
                                          {"chair", 0.53f, {173, 121, 134, 243}}};
  ASSERT_EQ(dets.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE(expected[i].label);
    EXPECT_EQ(dets[i].label, expected[i].label);
    EXPECT_NEAR(dets[i].score, expected[i].score, 0.02);
    EXPECT_GT(IoU(dets[i].box, expected[i].box), 0.9f) << dets[i].box;
    EXPECT_LE(dets[i].box.br().x, 640.0f);
    EXPECT_LE(dets[i].box.br().y, 480.0f);
  }
  EXPECT_EQ(dets[2].class_id, 41);  // "cup" is row 41 of the COCO list
}

TEST(DetectYolox, ScoreThresholdFilters) {
  DetectorConfig c;
  c.score_threshold = 0.7;
  auto dets = MakeDetector(c, ModelPaths())->Detect(ReadFrame(0), "f.jpg");
  ASSERT_EQ(dets.size(), 2u);
  EXPECT_EQ(dets[0].label, "dining table");
  EXPECT_EQ(dets[1].label, "chair");
}

// MANIFEST (yolo_fastest_1.1_xl_coco / yolox): frame 000500 -> cup, book, 2 chairs; frame 0 ->
// nothing. The cup and book boxes must agree with YOLOX's on the same frame.
TEST(DetectDarknet, RedkitchenFrame500MatchesManifest) {
  DetectorConfig c;
  c.backend = "darknet";
  auto det = MakeDetector(c, ModelPaths());
  EXPECT_EQ(det->name(), "darknet");
  EXPECT_TRUE(det->Detect(ReadFrame(0), "frame-000000.color.jpg").empty());
  const auto dets = det->Detect(ReadFrame(500), "frame-000500.color.jpg");
  std::multiset<std::string> labels;
  for (const auto& d : dets) labels.insert(d.label);
  EXPECT_EQ(labels, (std::multiset<std::string>{"book", "chair", "chair", "cup"}));
  const auto yolox = MakeDetector(DetectorConfig{}, ModelPaths())->Detect(ReadFrame(500), "f");
  for (const auto& d : dets) {
    float best = 0.0f;
    for (const auto& y : yolox) {
      if (y.label == d.label) best = std::max(best, IoU(y.box, d.box));
    }
    EXPECT_GT(best, 0.6f) << d.label << " " << d.box;
  }
}

TEST(DetectModels, MissingOrCorruptModelNamesTheFile) {
  TempDir dir("models");
  WriteText(dir.File("bad.onnx"), "this is not a protobuf");
  WriteText(dir.File("bad.weights"), std::string(100, '\x01'));
  auto paths = ModelPaths();
  paths.yolox_onnx = dir.str() + "/bad.onnx";
  ExpectInputError([&] { MakeDetector(DetectorConfig{}, paths); }, {dir.str() + "/bad.onnx"});
  paths.yolox_onnx = dir.str() + "/missing.onnx";
  ExpectInputError([&] { MakeDetector(DetectorConfig{}, paths); }, {"missing.onnx"});
  paths = ModelPaths();
  paths.yolox_classes = dir.str() + "/missing.txt";
  ExpectInputError([&] { MakeDetector(DetectorConfig{}, paths); }, {"missing.txt"});

  DetectorConfig c;
  c.backend = "darknet";
  paths = ModelPaths();
  paths.darknet_weights = dir.str() + "/bad.weights";
  ExpectInputError([&] { MakeDetector(c, paths); }, {"bad.weights"});
  c.backend = "florence";
  ExpectInputError([&] { MakeDetector(c, ModelPaths()); }, {"detector.backend", "florence"});
}

class DetectFile : public ::testing::Test {
 protected:
  DetectFile() : dir_("dets"), image_(480, 640, CV_8UC3, cv::Scalar::all(0)) {
    config_.backend = "file";
    config_.detections_dir = dir_.str();
  }
  std::vector<Detection> Run(const std::string& json) {
    WriteText(dir_.File("frame-000007.color.json"), json);
    return MakeDetector(config_, {})->Detect(image_, "some/dir/frame-000007.color.jpg");
  }
  TempDir dir_;
  cv::Mat image_;
  DetectorConfig config_;
};

TEST_F(DetectFile, ReadsBoxesLabelsScores) {
  const auto dets = Run(R"({"image": "frame-000007.color.jpg", "detections": [
      {"box": [10, 20, 110, 220], "label": "chair", "score": 0.5},
      {"box": [0, 0, 640.4, 480], "label": "dining table", "score": 0.9},
      {"box": [5, 5, 6, 6], "label": "cup", "score": 0.1},
      {"box": [300, 300, 400, 350], "label": "tv"}]})");
  // Threshold 0.3 drops the cup; the score defaults to 1; sorted by decreasing score.
  ASSERT_EQ(dets.size(), 3u);
  EXPECT_EQ(dets[0].label, "tv");
  EXPECT_FLOAT_EQ(dets[0].score, 1.0f);
  EXPECT_EQ(dets[1].label, "dining table");
  EXPECT_EQ(dets[1].box, cv::Rect2f(0, 0, 640, 480));  // 0.4 px overhang is clipped
  EXPECT_EQ(dets[2].box, cv::Rect2f(10, 20, 100, 200));
  EXPECT_EQ(dets[2].class_id, -1);
  EXPECT_TRUE(Run(R"({"detections": []})").empty());
}

TEST_F(DetectFile, ErrorsNameTheFile) {
  const std::string file = dir_.str() + "/frame-000007.color.json";
  ExpectInputError([&] { MakeDetector(config_, {})->Detect(image_, "frame-000008.color.jpg"); },
                   {dir_.str() + "/frame-000008.color.json"});
  ExpectInputError([&] { Run("{\"detections\": [ "); }, {file, "not valid JSON"});
  ExpectInputError([&] { Run("{\"dets\": []}"); }, {file, "detections"});
  ExpectInputError([&] { Run(R"({"detections": [{"label": "cup"}]})"); }, {file, "box"});
  ExpectInputError([&] { Run(R"({"detections": [{"box": [1, 1, 5, 5]}]})"); }, {file, "label"});
  ExpectInputError([&] { Run(R"({"detections": [{"box": [1, 1, 5], "label": "a"}]})"); },
                   {file, "box"});
  ExpectInputError([&] { Run(R"({"detections": [{"box": [5, 1, 5, 9], "label": "a"}]})"); },
                   {file, "x2 > x1"});
  ExpectInputError([&] { Run(R"({"detections": [{"box": [5, 1, 700, 9], "label": "a"}]})"); },
                   {file, "outside", "640x480"});
  ExpectInputError([&] { Run(R"({"detections": [{"box": [-9, 1, 7, 9], "label": "a"}]})"); },
                   {file, "outside"});
  ExpectInputError(
      [&] { Run(R"({"detections": [{"box": [1, 1, 7, 9], "label": "a", "score": 1.5}]})"); },
      {file, "score", "[0, 1]"});
  ExpectInputError(
      [&] { Run(R"({"detections": [{"box": [1, 1, 7, 9], "label": "a", "score": -0.1}]})"); },
      {file, "score"});
  ExpectInputError([&] { Run(R"({"image": "frame-000009.color.jpg", "detections": []})"); },
                   {file, "frame-000009.color.jpg"});
  config_.detections_dir.clear();
  ExpectInputError([&] { MakeDetector(config_, {}); }, {"detections_dir"});
}

}  // namespace
}  // namespace zeroreg
