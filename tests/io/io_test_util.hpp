// Helpers for the I/O tests: a self-cleaning temporary folder, small file writers and a checker
// for InputError messages.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "zeroreg/error.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg::testing_io {

namespace fs = std::filesystem;

// Unique folder under the system temp dir (pid + counter + test name), removed on destruction.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "zeroreg_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    if (info != nullptr) name += std::string("_") + info->name();
    path_ = fs::temp_directory_path() / name;
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }
  // Path of `relative` inside the folder, creating its parent folders.
  std::string File(const std::string& relative) const {
    const fs::path p = path_ / relative;
    fs::create_directories(p.parent_path());
    return p.string();
  }

 private:
  fs::path path_;
};

inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

// Uniform BGR colour image.
inline void WriteColor(const std::string& path, int width, int height,
                       cv::Scalar bgr = cv::Scalar(30, 120, 200)) {
  ASSERT_TRUE(cv::imwrite(path, cv::Mat(height, width, CV_8UC3, bgr))) << path;
}

// Uniform 16-bit depth image with raw value `raw`.
inline void WriteDepth(const std::string& path, int width, int height, uint16_t raw) {
  ASSERT_TRUE(cv::imwrite(path, cv::Mat(height, width, CV_16UC1, cv::Scalar(raw)))) << path;
}

// 16 numbers of a 4x4 row-major matrix, one row per line.
inline std::string MatrixText(const Transform& T) {
  std::string text;
  char buffer[64];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buffer, sizeof(buffer), "%.17g ", T(r, c));
      text += buffer;
    }
    text += "\n";
  }
  return text;
}

// A rigid transform with a non-trivial rotation.
inline Transform SomePose(double angle = 0.3, double tx = 0.5) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(tx, -0.25, 1.75);
  return T;
}

// Runs `fn`, expects an InputError whose message contains every one of `parts`.
template <typename Fn>
void ExpectInputError(Fn fn, std::initializer_list<std::string> parts) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "message '" << message << "' lacks '" << part << "'";
    }
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return;
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
}

}  // namespace zeroreg::testing_io
