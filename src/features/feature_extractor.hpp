// Local image features (paper §3.2, "Geometric Feature Extraction"): keypoints with L2-normalised
// descriptors, so that every backend is matched by cosine similarity (Eq. 3, S = G_P G_Q^T).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg {

struct ImageFeatures {
  std::vector<Eigen::Vector2f> keypoints;  // pixels of the input image (x right, y down)
  std::vector<float> scores;               // detector confidence, same order
  Eigen::MatrixXf descriptors;             // one L2-normalised row per keypoint

  int size() const { return static_cast<int>(keypoints.size()); }
  // Keeps the rows whose index is in `keep` (in that order).
  ImageFeatures Subset(const std::vector<int>& keep) const;
};

class FeatureExtractor {
 public:
  virtual ~FeatureExtractor() = default;
  virtual std::string name() const = 0;
  // `bgr` is CV_8UC3. Keypoints are sorted by decreasing score.
  virtual ImageFeatures Extract(const cv::Mat& bgr) const = 0;
};

// Builds the backend named by config.backend ("xfeat" or "sift"). Model files are resolved and
// checked in `assets_dir`. Throws InputError for an unknown backend or a missing/corrupt model.
// XFeat runs on the engine of `inference` (default: auto).
std::unique_ptr<FeatureExtractor> MakeFeatureExtractor(const FeatureConfig& config,
                                                       const std::string& assets_dir,
                                                       const InferenceConfig& inference = {});

}  // namespace zeroreg
