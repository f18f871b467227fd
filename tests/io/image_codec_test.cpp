// The PNG / JPEG codec (src/io/image_codec.hpp) against OpenCV's imgcodecs, which the library no
// longer links: the same pixels on the real frames of every scene in ../shared/data, on every
// PNG colour type the readers meet, and lossless round trips of what zeroreg writes.
#include "io/image_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "io/io_test_util.hpp"

namespace zeroreg::detail {
namespace {

namespace fs = std::filesystem;

const std::string kData = ZEROREG_REPO_DIR "/../shared/data/";

std::vector<std::uint8_t> Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::uint8_t> OpenCvEncode(const std::string& ext, const cv::Mat& image) {
  std::vector<std::uint8_t> out;
  EXPECT_TRUE(cv::imencode(ext, image, out));
  return out;
}

void ExpectSame(const cv::Mat& ours, const cv::Mat& theirs, const std::string& what) {
  ASSERT_FALSE(ours.empty()) << what;
  ASSERT_EQ(ours.type(), theirs.type()) << what;
  ASSERT_EQ(ours.size(), theirs.size()) << what;
  EXPECT_EQ(cv::norm(ours, theirs, cv::NORM_INF), 0.0) << what;
}

TEST(ImageCodec, RealFramesDecodeExactlyAsOpenCv) {
  for (const std::string scene : {"7scenes-redkitchen", "hololens-office", "tum-fr3-cabinet"}) {
    // The first three frames of the scene (their numbering starts at 0 or 3).
    std::vector<std::string> stems;
    for (const auto& entry : std::filesystem::directory_iterator(kData + scene + "/frames")) {
      const std::string name = entry.path().string();
      const std::string suffix = ".color.jpg";
      if (name.size() > suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        stems.push_back(name.substr(0, name.size() - suffix.size()));
      }
    }
    std::sort(stems.begin(), stems.end());
    ASSERT_GE(stems.size(), 3u) << scene;
    stems.resize(3);
    for (const std::string& stem : stems) {
      const std::vector<std::uint8_t> jpeg = Bytes(stem + ".color.jpg");
      const std::vector<std::uint8_t> png = Bytes(stem + ".depth.png");
      ASSERT_FALSE(jpeg.empty()) << stem;
      ASSERT_FALSE(png.empty()) << stem;
      ExpectSame(DecodeImage(jpeg, ImageMode::kColor), cv::imdecode(jpeg, cv::IMREAD_COLOR),
                 stem + ".color.jpg");
      const cv::Mat depth = DecodeImage(png, ImageMode::kUnchanged);
      ExpectSame(depth, cv::imdecode(png, cv::IMREAD_UNCHANGED), stem + ".depth.png");
      EXPECT_EQ(depth.type(), CV_16UC1);
      EXPECT_GT(cv::countNonZero(depth), static_cast<int>(depth.total() / 4))
          << "depth decoded as zeros";
    }
  }
}

TEST(ImageCodec, PngColourTypesAsOpenCvReadsThem) {
  cv::Mat bgr(37, 53, CV_8UC3), grey(37, 53, CV_8UC1), bgra(37, 53, CV_8UC4);
  cv::Mat deep_grey(37, 53, CV_16UC1), deep_bgr(37, 53, CV_16UC3);
  cv::RNG rng(7);
  for (cv::Mat* m : {&bgr, &grey, &bgra, &deep_grey, &deep_bgr}) {
    rng.fill(*m, cv::RNG::UNIFORM, 0, m->depth() == CV_16U ? 65536 : 256);
  }
  for (const cv::Mat* m : {&bgr, &grey, &bgra, &deep_grey, &deep_bgr}) {
    const std::vector<std::uint8_t> file = OpenCvEncode(".png", *m);
    const std::string what = "type " + std::to_string(m->type());
    ExpectSame(DecodeImage(file, ImageMode::kColor), cv::imdecode(file, cv::IMREAD_COLOR), what);
    ExpectSame(DecodeImage(file, ImageMode::kUnchanged), cv::imdecode(file, cv::IMREAD_UNCHANGED),
               what);
  }
  // A grey JPEG in colour mode is replicated to three channels, as cv::IMREAD_COLOR does.
  const std::vector<std::uint8_t> grey_jpeg = OpenCvEncode(".jpg", grey);
  ExpectSame(DecodeImage(grey_jpeg, ImageMode::kColor), cv::imdecode(grey_jpeg, cv::IMREAD_COLOR),
             "grey JPEG");
}

TEST(ImageCodec, WhatZeroregWritesReadsBackUnchanged) {
  cv::Mat depth_mm(48, 64, CV_16UC1), bgr(48, 64, CV_8UC3), mask(48, 64, CV_8UC1);
  cv::RNG rng(3);
  rng.fill(depth_mm, cv::RNG::UNIFORM, 0, 65536);
  rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
  rng.fill(mask, cv::RNG::UNIFORM, 0, 256);
  for (const cv::Mat* m : {&depth_mm, &bgr, &mask}) {
    const std::vector<std::uint8_t> file = EncodePng(*m);
    ExpectSame(DecodeImage(file, ImageMode::kUnchanged), *m, "ours");
    ExpectSame(cv::imdecode(file, cv::IMREAD_UNCHANGED), *m, "OpenCV reading ours");
  }
  // JPEG is lossy: OpenCV must read our file as we do, and close to the original.
  const std::vector<std::uint8_t> jpeg = EncodeJpeg(bgr, 95);
  const cv::Mat ours = DecodeImage(jpeg, ImageMode::kColor);
  ExpectSame(ours, cv::imdecode(jpeg, cv::IMREAD_COLOR), "our JPEG");
  cv::Mat smooth;
  cv::Mat(48, 64, CV_8UC3, cv::Scalar(40, 120, 200)).copyTo(smooth);
  EXPECT_LE(cv::norm(DecodeImage(EncodeJpeg(smooth, 90), ImageMode::kColor), smooth, cv::NORM_INF),
            2.0);
}

// A picture that cannot be written says why (the system's reason), and one that was there before
// is replaced whole or not at all.
TEST(ImageCodec, WriteFailureSaysWhy) {
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "/dev/full is absent";
  zeroreg::testing_io::TempDir dir;
  const std::string full = dir.File("full.png");
  fs::create_symlink("/dev/full", full);
  const cv::Mat image(48, 64, CV_8UC3, cv::Scalar(40, 120, 200));
  try {
    WriteImageFile(full, image);
    FAIL() << "no error writing to a full disk";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("full.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  const std::string path = dir.File("picture.png");
  ASSERT_TRUE(WriteImageFile(path, image));
  EXPECT_EQ(DecodeImage(Bytes(path), ImageMode::kColor).size(), image.size());
}

TEST(ImageCodec, BadBytesAreErrorsOrNotAnImage) {
  EXPECT_TRUE(DecodeImage({}, ImageMode::kColor).empty());
  EXPECT_TRUE(DecodeImage({'B', 'M', 0, 0, 0, 0}, ImageMode::kColor).empty());  // BMP: not ours
  std::vector<std::uint8_t> png = EncodePng(cv::Mat(20, 20, CV_8UC1, cv::Scalar(9)));
  png.resize(png.size() / 2);
  EXPECT_THROW(DecodeImage(png, ImageMode::kUnchanged), std::runtime_error);
  std::vector<std::uint8_t> jpeg = EncodeJpeg(cv::Mat(20, 20, CV_8UC3, cv::Scalar(1, 2, 3)), 90);
  for (size_t i = 20; i < 200 && i < jpeg.size(); ++i) jpeg[i] = 0x5A;  // wreck the tables
  EXPECT_THROW(DecodeImage(jpeg, ImageMode::kColor), std::runtime_error);
  EXPECT_THROW(EncodePng(cv::Mat(4, 4, CV_32FC1)), std::invalid_argument);
  EXPECT_THROW(EncodeJpeg(cv::Mat(4, 4, CV_16UC1), 90), std::invalid_argument);
}

}  // namespace
}  // namespace zeroreg::detail
