#include "features/sift_extractor.hpp"

#include <algorithm>
#include <numeric>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace zeroreg {

ImageFeatures SiftExtractor::Extract(const cv::Mat& bgr) const {
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  // nfeatures = 0: keep all, then sort ourselves so that ties are broken deterministically.
  cv::Ptr<cv::SIFT> sift = cv::SIFT::create(0, 3, config_.sift_contrast_threshold);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  sift->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);

  std::vector<int> order(keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return keypoints[a].response > keypoints[b].response; });
  if (static_cast<int>(order.size()) > config_.max_keypoints) order.resize(config_.max_keypoints);

  ImageFeatures out;
  out.descriptors.resize(static_cast<Eigen::Index>(order.size()), descriptors.cols);
  for (size_t r = 0; r < order.size(); ++r) {
    const cv::KeyPoint& kp = keypoints[order[r]];
    out.keypoints.emplace_back(kp.pt.x, kp.pt.y);
    out.scores.push_back(kp.response);
    const float* row = descriptors.ptr<float>(order[r]);
    double l1 = 0;
    for (int c = 0; c < descriptors.cols; ++c) l1 += std::abs(row[c]);
    l1 = std::max(l1, 1e-12);
    for (int c = 0; c < descriptors.cols; ++c) {
      out.descriptors(static_cast<Eigen::Index>(r), c) =
          static_cast<float>(std::sqrt(std::abs(row[c]) / l1));
    }
  }
  return out;
}

}  // namespace zeroreg
