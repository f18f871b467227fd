// XFeat sparse keypoints and 64-d descriptors (Potje et al., CVPR 2024), ONNX, run by the engine
// of inference.engine (ONNX Runtime or OpenCV DNN, src/inference/onnx_model.hpp).
// Pre/post-processing follows ../shared/models/xfeat/MANIFEST.md: RGB/255 input, the image scaled
// so its longer side is 640 px and padded to multiples of 32 (xfeat_any_size.onnx) or to the
// export's fixed 640x640 (XFeatInput::square); 65-channel keypoint logits -> softmax,
// drop the dustbin, depth-to-space to a full-resolution heatmap; 5x5 non-maximum suppression; score
// = heatmap x reliability; descriptors sampled bilinearly from the stride-8 map and L2-normalised.
#pragma once

#include <memory>

#include "features/feature_extractor.hpp"
#include "inference/onnx_model.hpp"

namespace zeroreg {

// How XFeat is fed an image. The pipeline runs the defaults. The alternatives are what the
// defaults replaced; they are not settings (docs/SPEED.md measured both against the defaults) and
// stay for the tests and `zeroreg bench-models` that measure against them; the square is also
// what OpenCV DNN runs.
struct XFeatInput {
  // The export's fixed 640x640 (the scaled image padded with its mean colour) instead of the
  // image's own size padded to multiples of 32 (a quarter of a 640x480 frame's work went to the
  // fill).
  bool square = false;
  // At the image's own size: the network normalises the image as it did on the padded square
  // (the flat fill diluted the grey variance, raising the contrast the network saw by
  // sqrt(640 x 640 / input area): 1.15 for 640x480), so the features are those every default was
  // measured with; false = by the image's own variance, as upstream XFeat does.
  bool square_contrast = true;
};

class XFeatExtractor : public FeatureExtractor {
 public:
  // `model_path` is the file ModelFile names for this engine and input.
  XFeatExtractor(const std::string& model_path, const FeatureConfig& config,
                 const InferenceConfig& inference = {}, XFeatInput input = {});
  std::string name() const override { return "xfeat"; }
  ImageFeatures Extract(const cv::Mat& bgr) const override;

  // Whether XFeat runs on the export's fixed 640x640 square: when asked (XFeatInput::square), and
  // on OpenCV DNN, whose 4.6 importer needs every shape when it loads a model and so cannot load
  // the any-size model.
  static bool UsesSquareInput(const InferenceConfig& inference, const XFeatInput& input = {});
  // The model file for that choice, relative to the assets folder.
  static std::string ModelFile(const InferenceConfig& inference, const XFeatInput& input = {});

  // The network's input size for an image: 640x640 for the square export; otherwise the image
  // scaled so its longer side is 640 px, rounded up to multiples of 32 (640x480 stays 640x480,
  // a 540x360 HoloLens frame becomes 640x448).
  static cv::Size InputSize(const cv::Size& image, bool square_input);

  static constexpr int kInputSize = 640;    // longer side; the square export's fixed size
  static constexpr int kCell = 8;           // descriptor / logit stride
  static constexpr int kSizeMultiple = 32;  // the backbone's coarsest stride

 private:
  FeatureConfig config_;
  XFeatInput input_;
  bool square_input_;
  std::unique_ptr<OnnxModel> model_;  // thread-safe Run
};

}  // namespace zeroreg
