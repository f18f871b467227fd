// Single-file readers (intrinsics, poses, colour and depth images) and LoadView.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>
#include <vector>

#include "io/image_checks.hpp"
#include "io/image_file.hpp"
#include "io/shown.hpp"
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
    throw MakeInputError(where, "focal length fx = " + ShownNumber(k.fx) +
                                    ", fy = " + ShownNumber(k.fy) +
                                    " is invalid; expected fx > 0 and fy > 0 (pixels)");
  }
  const bool sized = k.width > 0 && k.height > 0;
  constexpr double kWidestImage = 65535;  // the largest side scan.json and JPEG accept
  const double width = sized ? k.width : kWidestImage;
  const double height = sized ? k.height : kWidestImage;
  const double side = std::max(width, height);
  const double min_focal = sized ? side / 100 : 0.01;  // unsized: an image may be 1 pixel wide
  const double max_focal = side * 1000;
  const std::string image =
      sized ? "a " + std::to_string(k.width) + "x" + std::to_string(k.height) + " image"
            : "any image up to 65535 pixels wide";
  for (const auto& [name, f] : {std::pair<const char*, double>{"fx", k.fx}, {"fy", k.fy}}) {
    if (f < min_focal || f > max_focal) {
      throw MakeInputError(where, std::string("focal length ") + name + " = " + ShownNumber(f) +
                                      " pixels is implausible for " + image + "; expected " +
                                      ShownNumber(min_focal) + " to " + ShownNumber(max_focal) +
                                      " pixels (1/100 to 1000 times the image side: a field of "
                                      "view between 0.06 and 179 degrees)");
    }
  }
  const auto principal = [&](const char* name, double c, double size) {
    if (c < -size / 2 || c > size * 1.5) {
      throw MakeInputError(where, std::string("principal point ") + name + " = " + ShownNumber(c) +
                                      " pixels is far outside " + image + "; expected " +
                                      ShownNumber(-size / 2) + " to " + ShownNumber(size * 1.5) +
                                      " (near the image centre)");
    }
  };
  principal("cx", k.cx, width);
  principal("cy", k.cy, height);
}

void CheckDepthRange(const cv::Mat& depth_m, const std::string& where,
                     const std::string& scale_source, double depth_scale) {
  std::vector<float> valid;
  valid.reserve(static_cast<size_t>(depth_m.total()));
  for (int r = 0; r < depth_m.rows; ++r) {
    const float* row = depth_m.ptr<float>(r);
    for (int c = 0; c < depth_m.cols; ++c) {
      if (row[c] != 0.0f) valid.push_back(row[c]);
    }
  }
  if (valid.empty()) return;  // "no valid pixel" is reported by the caller
  const std::string scale = depth_scale > 0 ? scale_source + " = " + ShownNumber(depth_scale)
                                            : std::string("depth in metres");
  const std::string expected =
      "; expected a depth sensor's range (median depth " + ShownNumber(kMinMedianDepthM) + " to " +
      ShownNumber(kMaxMedianDepthM) + " m)" +
      (depth_scale > 0 ? ": check " + scale_source +
                             " (raw units per metre: 1000 for millimetres, 5000 for TUM)"
                       : std::string(": is the depth in metres?"));
  for (float d : valid) {
    if (!std::isfinite(d)) {
      throw MakeInputError(where, scale + " gives an infinite depth" + expected);
    }
  }
  const auto middle = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2);
  std::nth_element(valid.begin(), middle, valid.end());
  const double median = *middle;
  if (median < kMinMedianDepthM || median > kMaxMedianDepthM) {
    const auto [lowest, highest] = std::minmax_element(valid.begin(), valid.end());
    throw MakeInputError(where, scale + " gives depths from " + ShownNumber(*lowest) + " to " +
                                    ShownNumber(*highest) + " m (median " + ShownNumber(median) +
                                    " m)" + expected);
  }
}

int CountValidDepth(const cv::Mat& depth_m) { return cv::countNonZero(depth_m > 0.0f); }

View MakeCheckedView(const std::string& name, const cv::Mat& color, const std::string& color_path,
                     const cv::Mat& depth, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size,
                     const std::string& intrinsics_source) {
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
  CheckIntrinsics(view.intrinsics,
                  intrinsics_source.empty() ? "intrinsics of " + name : intrinsics_source);
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

namespace detail {

View LoadCheckedView(const std::string& color_path, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size,
                     const std::string& intrinsics_source, double depth_scale,
                     const std::string& scale_source) {
  const cv::Mat color = ReadColorImage(color_path);
  const cv::Mat depth = ReadDepthImage(depth_path, depth_scale);
  CheckDepthRange(depth, depth_path, scale_source, depth_scale);
  return MakeCheckedView(color_path, color, color_path, depth, depth_path, intrinsics_without_size,
                         intrinsics_source);
}

}  // namespace detail

View LoadView(const std::string& color_path, const std::string& depth_path,
              const Intrinsics& intrinsics_without_size, double depth_scale) {
  return detail::LoadCheckedView(color_path, depth_path, intrinsics_without_size, "", depth_scale,
                                 "depth_scale");
}

}  // namespace zeroreg
