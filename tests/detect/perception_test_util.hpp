// Helpers shared by the detection and segmentation tests: model and frame paths, a frame reader,
// box IoU, a self-cleaning temporary folder, and a check that an InputError names a given file.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <time.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "detect/detector.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg::perception_test {

inline std::string AssetsDir() { return std::string(ZEROREG_REPO_DIR) + "/assets"; }
inline std::string FramePath(int frame, const std::string& suffix) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame-%06d.%s", frame, suffix.c_str());
  return std::string(ZEROREG_REPO_DIR) + "/../shared/data/7scenes-redkitchen/frames/" + name;
}

// Frame `id` of the redkitchen scene as BGR (a test failure, and an empty image, if unreadable).
inline cv::Mat ReadFrame(int id) {
  cv::Mat img = cv::imread(FramePath(id, "color.jpg"), cv::IMREAD_COLOR);
  EXPECT_FALSE(img.empty()) << FramePath(id, "color.jpg");
  return img;
}

// Intersection over union of two boxes.
inline float IoU(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float inter = (a & b).area();
  return inter / (a.area() + b.area() - inter);
}

inline DetectorModelPaths ModelPaths() {
  DetectorModelPaths p;
  p.yolox_onnx = AssetsDir() + "/yolox_nano_coco/yolox_nano.onnx";
  p.yolox_classes = AssetsDir() + "/yolox_nano_coco/coco_classes.txt";
  p.darknet_cfg = AssetsDir() + "/yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.cfg";
  p.darknet_weights = AssetsDir() + "/yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.weights";
  p.darknet_classes = AssetsDir() + "/yolo_fastest_1.1_xl_coco/coco_classes.txt";
  p.picodet_onnx = AssetsDir() + "/picodet_s_416_coco/picodet_s_416_coco.onnx";
  p.picodet_opencv_onnx = AssetsDir() + "/picodet_s_416_coco/picodet_s_416_coco.opencv.onnx";
  p.picodet_classes = AssetsDir() + "/picodet_s_416_coco/coco.names";
  return p;
}

// Unique folder under the system temp dir, removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("zeroreg_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string str() const { return path_.string(); }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// CPU time of the calling thread: unlike wall time, barely affected by other users of the cores.
inline double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

// Runs `f` and checks that it throws InputError whose message contains every string in `needles`
// (typically the file name and a word describing the problem).
inline void ExpectInputError(const std::function<void()>& f,
                             const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "expected InputError mentioning '" << needles.front() << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& n : needles) {
      EXPECT_NE(msg.find(n), std::string::npos) << "message '" << msg << "' lacks '" << n << "'";
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
  }
}

}  // namespace zeroreg::perception_test
