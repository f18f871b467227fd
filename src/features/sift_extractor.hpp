// SIFT (OpenCV, no model file needed) with RootSIFT descriptors: L1-normalise, square root, which
// is L2-normalised and makes the dot product a Hellinger kernel (Arandjelović & Zisserman 2012).
#pragma once

#include "features/feature_extractor.hpp"

namespace zeroreg {

class SiftExtractor : public FeatureExtractor {
 public:
  explicit SiftExtractor(const FeatureConfig& config) : config_(config) {}
  std::string name() const override { return "sift"; }
  ImageFeatures Extract(const cv::Mat& bgr) const override;

 private:
  FeatureConfig config_;
};

}  // namespace zeroreg
