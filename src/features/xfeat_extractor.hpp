// XFeat sparse keypoints and 64-d descriptors (Potje et al., CVPR 2024), ONNX, run by the engine
// of inference.engine (ONNX Runtime or OpenCV DNN, src/inference/onnx_model.hpp).
// Pre/post-processing follows ../shared/models/xfeat/MANIFEST.md: fixed 640x640 RGB/255 input;
// 65-channel keypoint logits -> softmax, drop the dustbin, depth-to-space to a full-resolution
// heatmap; 5x5 non-maximum suppression; score = heatmap x reliability; descriptors sampled
// bilinearly from the stride-8 map and L2-normalised.
#pragma once

#include <memory>

#include "features/feature_extractor.hpp"
#include "inference/onnx_model.hpp"

namespace zeroreg {

class XFeatExtractor : public FeatureExtractor {
 public:
  XFeatExtractor(const std::string& model_path, const FeatureConfig& config,
                 const InferenceConfig& inference = {});
  std::string name() const override { return "xfeat"; }
  ImageFeatures Extract(const cv::Mat& bgr) const override;

  static constexpr int kInputSize = 640;  // the export has fixed 1x3x640x640 input
  static constexpr int kCell = 8;         // descriptor / logit stride

 private:
  FeatureConfig config_;
  std::unique_ptr<OnnxModel> model_;  // thread-safe Run
};

}  // namespace zeroreg
