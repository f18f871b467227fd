// Statistics of a mask over a depth image, shared by the segmentation tests.
#pragma once

#include <algorithm>
#include <opencv2/core.hpp>
#include <vector>

namespace zeroreg::mask_test {

// Interquartile range of the valid (> 0) depths under `mask` (metres); 0 with fewer than 4.
inline double DepthIqr(const cv::Mat& depth, const cv::Mat& mask) {
  std::vector<float> v;
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      const float d = depth.at<float>(y, x);
      if (mask.at<uchar>(y, x) && d > 0.0f) v.push_back(d);
    }
  }
  if (v.size() < 4) return 0.0;
  std::sort(v.begin(), v.end());
  return v[3 * v.size() / 4] - v[v.size() / 4];
}

}  // namespace zeroreg::mask_test
