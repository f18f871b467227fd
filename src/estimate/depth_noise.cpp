#include "estimate/depth_noise.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "estimate/lift.hpp"

namespace zeroreg {
namespace {

// The upper median (element size/2 in order) of a non-empty vector; reorders it.
template <typename T>
double UpperMedian(std::vector<T>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return static_cast<double>(*mid);
}

}  // namespace

std::optional<double> MeasureDepthNoiseAt1m(const View& view) {
  const cv::Mat& depth = view.depth;
  if (depth.empty() || depth.type() != CV_32FC1) return std::nullopt;
  // Differences k px apart, centred on one pixel per grid cell (every k-th row and column): plenty,
  // ~38000 differences at 640x480.
  const int k = PixelGrid{}.StrideFor(depth.cols);
  std::vector<float> differences;
  differences.reserve(static_cast<size_t>(depth.rows / k) * (depth.cols / k) * 2);
  const auto inverse = [&](int y, int x) {
    const float z = depth.at<float>(y, x);
    return z > 0 ? 1.0f / z : 0.0f;
  };
  for (int y = k; y + k < depth.rows; y += k) {
    for (int x = k; x + k < depth.cols; x += k) {
      const float c = inverse(y, x);
      if (c == 0) continue;
      const float left = inverse(y, x - k), right = inverse(y, x + k);
      if (left > 0 && right > 0) differences.push_back(left + right - 2 * c);
      const float up = inverse(y - k, x), down = inverse(y + k, x);
      if (up > 0 && down > 0) differences.push_back(up + down - 2 * c);
    }
  }
  if (differences.size() < 1000) return std::nullopt;
  const double centre = UpperMedian(differences);
  for (float& d : differences) d = static_cast<float>(std::abs(d - centre));
  // MAD -> standard deviation of a normal (1.4826), then the spread sqrt(6) of the sum of three
  // independent readings with weights 1, 1, -2.
  return 1.4826 * UpperMedian(differences) / std::sqrt(6.0);
}

std::optional<double> MeasureDepthNoiseAt1m(const Scan& scan) {
  std::vector<double> per_view;
  for (const View& view : scan.views) {
    if (const auto a = MeasureDepthNoiseAt1m(view)) per_view.push_back(*a);
  }
  if (per_view.empty()) return std::nullopt;
  return UpperMedian(per_view);
}

}  // namespace zeroreg
