// Single-file readers (intrinsics, poses, colour and depth images) and LoadView.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "io/image_checks.hpp"
#include "io/image_file.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

namespace detail {

std::string SizeString(const cv::Mat& image) {
  return std::to_string(image.cols) + "x" + std::to_string(image.rows);
}

void CheckIntrinsics(const Intrinsics& k, const std::string& where) {
  if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) ||
      !std::isfinite(k.cy)) {
    throw MakeInputError(where, "non-finite intrinsics; expected finite fx, fy, cx, cy");
  }
  if (k.fx <= 0.0 || k.fy <= 0.0) {
    std::ostringstream msg;
    msg << "focal length fx = " << k.fx << ", fy = " << k.fy
        << " is invalid; expected fx > 0 and fy > 0 (pixels)";
    throw MakeInputError(where, msg.str());
  }
}

int CountValidDepth(const cv::Mat& depth_m) { return cv::countNonZero(depth_m > 0.0f); }

View MakeCheckedView(const std::string& name, const cv::Mat& color, const std::string& color_path,
                     const cv::Mat& depth, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size) {
  if (color.size() != depth.size()) {
    throw MakeInputError(color_path, "colour image is " + SizeString(color) + " but depth image " +
                                         depth_path + " is " + SizeString(depth) +
                                         "; expected the same size");
  }
  if (CountValidDepth(depth) == 0) {
    throw MakeInputError(depth_path,
                         "depth image has no valid pixel (all 0 or 65535); expected some depth");
  }
  View view;
  view.name = name;
  view.color_file = color_path;
  view.color = color;
  view.depth = depth;
  view.intrinsics = intrinsics_without_size;
  view.intrinsics.width = depth.cols;
  view.intrinsics.height = depth.rows;
  CheckIntrinsics(view.intrinsics, "intrinsics of " + name);
  return view;
}

}  // namespace detail

Intrinsics ReadIntrinsicsFile(const std::string& path, int width, int height) {
  const std::vector<double> n = detail::ReadNumbers(path, "intrinsics file");
  if (n.size() != 9 && n.size() != 16) {
    throw MakeInputError(path, "intrinsics file holds " + std::to_string(n.size()) +
                                   " numbers; expected 9 (3x3 camera matrix) or 16 (4x4)");
  }
  for (double v : n) {
    if (!std::isfinite(v)) {
      throw MakeInputError(path,
                           "intrinsics file holds a non-finite value; expected finite numbers");
    }
  }
  const size_t stride = n.size() == 9 ? 3 : 4;
  auto at = [&](size_t r, size_t c) { return n[r * stride + c]; };
  Intrinsics k;
  k.fx = at(0, 0);
  k.fy = at(1, 1);
  k.cx = at(0, 2);
  k.cy = at(1, 2);
  k.width = width;
  k.height = height;
  detail::CheckIntrinsics(k, path);
  if (std::abs(at(1, 0)) > 1e-9 || std::abs(at(2, 0)) > 1e-9 || std::abs(at(2, 1)) > 1e-9 ||
      std::abs(at(2, 2) - 1.0) > 1e-6) {
    throw MakeInputError(
        path, "not a camera matrix; expected [fx s cx; 0 fy cy; 0 0 1] (last row 0 0 1)");
  }
  return k;
}

Transform ReadPoseFile(const std::string& path) {
  return detail::RigidFromNumbers(detail::ReadNumbers(path, "pose file"), path);
}

cv::Mat ReadColorImage(const std::string& path) {
  cv::Mat image = detail::ReadImageFile(path, "colour image", detail::ImageMode::kColor);
  if (image.empty()) {
    throw MakeInputError(path,
                         "colour image cannot be decoded (corrupt or unsupported format); expected "
                         "a PNG or JPEG file");
  }
  return image;  // ImageMode::kColor always gives CV_8UC3 BGR.
}

cv::Mat ReadDepthImage(const std::string& path, double depth_scale) {
  detail::CheckDepthScale(depth_scale, path);
  const cv::Mat raw = detail::ReadImageFile(path, "depth image", detail::ImageMode::kUnchanged);
  if (raw.empty()) {
    throw MakeInputError(
        path,
        "depth image cannot be decoded (corrupt or unsupported format); expected a "
        "16-bit single-channel PNG");
  }
  if (raw.type() != CV_16UC1) {
    const int depth = raw.depth();
    const char* bits = depth == CV_8U || depth == CV_8S     ? "8-bit"
                       : depth == CV_16U || depth == CV_16S ? "16-bit"
                       : depth == CV_32F || depth == CV_32S ? "32-bit"
                                                            : "64-bit";
    throw MakeInputError(path, std::string("depth image is ") + bits + " with " +
                                   std::to_string(raw.channels()) +
                                   " channel(s); expected a 16-bit single-channel PNG (uint16)");
  }
  cv::Mat metres(raw.size(), CV_32FC1);
  for (int r = 0; r < raw.rows; ++r) {
    const uint16_t* src = raw.ptr<uint16_t>(r);
    float* dst = metres.ptr<float>(r);
    for (int c = 0; c < raw.cols; ++c) {
      // 0 = no measurement; 65535 = saturated / invalid (occurs in 7-Scenes).
      dst[c] = (src[c] == 0 || src[c] == 65535) ? 0.0f : static_cast<float>(src[c] / depth_scale);
    }
  }
  return metres;
}

View LoadView(const std::string& color_path, const std::string& depth_path,
              const Intrinsics& intrinsics_without_size, double depth_scale) {
  const cv::Mat color = ReadColorImage(color_path);
  const cv::Mat depth = ReadDepthImage(depth_path, depth_scale);
  return detail::MakeCheckedView(color_path, color, color_path, depth, depth_path,
                                 intrinsics_without_size);
}

}  // namespace zeroreg
