#include <algorithm>
#include <cstdint>
#include <fstream>

#include "detect/backends.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Number of float32 parameters a Darknet .weights file holds after its header (major, minor,
// revision as int32, then "seen" as int64 from version 0.2 on, int32 before), or -1 if the header
// cannot be read.
long long WeightsFileFloatCount(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return -1;
  const long long size = static_cast<long long>(in.tellg());
  in.seekg(0);
  std::int32_t version[3] = {0, 0, 0};
  in.read(reinterpret_cast<char*>(version), sizeof(version));
  if (!in) return -1;
  const long long header = (version[0] * 10 + version[1] >= 2) ? 20 : 16;
  return size < header ? -1 : (size - header) / 4;
}

}  // namespace

void DarknetDetector::CheckWeightsSize(const std::string& weights_path) const {
  // OpenCV's Darknet importer reads the weights without checking for end of file, so a truncated
  // file loads "successfully" with garbage parameters. Every value of the file belongs to a
  // convolution (weights, biases) or its batch norm (scale, mean, variance), which is exactly what
  // the loaded layers hold: compare the counts.
  long long needed = 0;
  for (const std::string& layer_name : net_.getLayerNames()) {
    const cv::Ptr<cv::dnn::Layer> layer = net_.getLayer(layer_name);
    if (layer->type != "Convolution" && layer->type != "BatchNorm") continue;
    for (const cv::Mat& blob : layer->blobs) needed += static_cast<long long>(blob.total());
  }
  const long long have = WeightsFileFloatCount(weights_path);
  if (have < needed) {
    throw MakeInputError(weights_path, "holds " + std::to_string(std::max(have, 0LL)) +
                                           " parameters but the cfg's layers need " +
                                           std::to_string(needed) +
                                           " (truncated file or mismatched cfg?)");
  }
}

DarknetDetector::DarknetDetector(const std::string& cfg_path, const std::string& weights_path,
                                 const std::string& classes_path, const DetectorConfig& config)
    : config_(config), weights_path_(weights_path) {
  detail::RequireReadableFile(cfg_path, "Darknet cfg");
  detail::RequireReadableFile(weights_path, "Darknet weights");
  classes_ = detail::ReadClassNames(classes_path);
  try {
    net_ = cv::dnn::readNetFromDarknet(cfg_path, weights_path);
  } catch (const cv::Exception& e) {
    throw MakeInputError(weights_path, "cannot load Darknet network with cfg " + cfg_path +
                                           " (corrupt or mismatched files?): " + e.what());
  }
  if (net_.empty()) throw MakeInputError(weights_path, "Darknet network loaded empty");
  CheckWeightsSize(weights_path);
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  output_names_ = net_.getUnconnectedOutLayersNames();
}

std::vector<Detection> DarknetDetector::Detect(const cv::Mat& bgr, const std::string& image_name) {
  detail::RequireBgrImage(bgr, image_name);
  // Plain resize (the cfg has no letterbox), RGB, /255 (MANIFEST "Input").
  const cv::Mat blob = cv::dnn::blobFromImage(bgr, 1.0 / 255.0, cv::Size(kInputSize, kInputSize),
                                              cv::Scalar(), /*swapRB=*/true, /*crop=*/false);
  std::vector<cv::Mat> outs;
  try {
    std::lock_guard<std::mutex> lock(net_mutex_);
    net_.setInput(blob);
    net_.forward(outs, output_names_);
    // The outputs share the net's buffers, which the next forward overwrites.
    for (cv::Mat& out : outs) out = out.clone();
  } catch (const cv::Exception& e) {
    throw MakeInputError(weights_path_, std::string("forward pass failed: ") + e.what());
  }
  const int num_classes = static_cast<int>(classes_.size());
  const float W = static_cast<float>(bgr.cols), H = static_cast<float>(bgr.rows);
  const cv::Rect2f image_rect(0.0f, 0.0f, W, H);
  std::vector<Detection> candidates;
  for (const cv::Mat& out : outs) {
    if (out.dims != 2 || out.cols != 5 + num_classes) {
      throw MakeInputError(weights_path_, "output layer has " + std::to_string(out.cols) +
                                              " columns, expected " +
                                              std::to_string(5 + num_classes));
    }
    for (int i = 0; i < out.rows; ++i) {
      const float* p = out.ptr<float>(i);
      // Columns 5.. are already objectness * class probability (OpenCV region layer).
      int best = 0;
      for (int k = 1; k < num_classes; ++k) {
        if (p[5 + k] > p[5 + best]) best = k;
      }
      const float score = p[5 + best];
      if (score < config_.score_threshold) continue;
      const float w = p[2] * W, h = p[3] * H;
      cv::Rect2f box(p[0] * W - 0.5f * w, p[1] * H - 0.5f * h, w, h);
      box &= image_rect;
      if (box.width <= 0.0f || box.height <= 0.0f) continue;
      candidates.push_back({box, classes_[best], score, best});
    }
  }
  return detail::NonMaxSuppressionPerClass(candidates, config_.nms_iou);
}

}  // namespace zeroreg
