#include <cmath>
#include <opencv2/imgproc.hpp>

#include "detect/backends.hpp"
#include "inference/image_tensor.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {

YoloxDetector::YoloxDetector(const std::string& onnx_path, const std::string& classes_path,
                             const DetectorConfig& config, const InferenceConfig& inference)
    : config_(config), onnx_path_(onnx_path) {
  detail::RequireReadableFile(onnx_path, "YOLOX ONNX model");
  classes_ = detail::ReadClassNames(classes_path);
  model_ = LoadOnnxModel(onnx_path, "YOLOX ONNX model (corrupt or not the YOLOX-Nano export?)",
                         inference);
}

std::vector<Detection> YoloxDetector::Detect(const cv::Mat& bgr, const std::string& image_name) {
  detail::RequireBgrImage(bgr, image_name);
  double r = 1.0;
  const cv::Mat canvas = detail::LetterboxTopLeft(bgr, kInputSize, &r);
  // Raw 0-255 BGR, no mean/std: the export bakes no normalisation in (MANIFEST "Input").
  const std::vector<float> blob = ImagePlanes(canvas, 1.0, /*swap_rb=*/false);
  const std::vector<Tensor> outputs =
      model_->Run({{"images", {1, 3, kInputSize, kInputSize}, blob.data()}}, {"output"});
  const std::vector<float>& out = outputs[0].data;
  const int num_cols = 5 + static_cast<int>(classes_.size());
  static constexpr int kStrides[3] = {8, 16, 32};
  int expected_rows = 0;
  for (int s : kStrides) expected_rows += (kInputSize / s) * (kInputSize / s);
  if (out.size() != static_cast<size_t>(expected_rows) * num_cols) {
    throw MakeInputError(onnx_path_, "output has " + std::to_string(out.size()) +
                                         " values, expected 1x" + std::to_string(expected_rows) +
                                         "x" + std::to_string(num_cols));
  }
  const float* data = out.data();
  const cv::Rect2f image_rect(0.0f, 0.0f, static_cast<float>(bgr.cols),
                              static_cast<float>(bgr.rows));
  std::vector<Detection> candidates;
  int row = 0;
  // Rows are the grid cells of strides 8, 16, 32 in that order, row-major (y, x) in each.
  for (int stride : kStrides) {
    const int cells = kInputSize / stride;
    for (int gy = 0; gy < cells; ++gy) {
      for (int gx = 0; gx < cells; ++gx, ++row) {
        const float* p = data + static_cast<size_t>(row) * num_cols;
        const float obj = p[4];
        if (obj < config_.score_threshold) continue;  // score = obj * cls <= obj
        int best = 0;
        for (int k = 1; k < static_cast<int>(classes_.size()); ++k) {
          if (p[5 + k] > p[5 + best]) best = k;
        }
        const float score = obj * p[5 + best];
        if (score < config_.score_threshold) continue;
        const double cx = (p[0] + gx) * stride, cy = (p[1] + gy) * stride;
        const double w = std::exp(p[2]) * stride, h = std::exp(p[3]) * stride;
        cv::Rect2f box(static_cast<float>((cx - 0.5 * w) / r),
                       static_cast<float>((cy - 0.5 * h) / r), static_cast<float>(w / r),
                       static_cast<float>(h / r));
        box &= image_rect;
        if (box.width <= 0.0f || box.height <= 0.0f) continue;
        candidates.push_back({box, classes_[best], score, best});
      }
    }
  }
  return detail::NonMaxSuppressionPerClass(candidates, config_.nms_iou);
}

}  // namespace zeroreg
