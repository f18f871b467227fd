#include "detect/detector.hpp"

#include <algorithm>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "detect/backends.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {

std::unique_ptr<Detector> MakeDetector(const DetectorConfig& config,
                                       const DetectorModelPaths& paths,
                                       const InferenceConfig& inference) {
  if (!(config.score_threshold >= 0.0 && config.score_threshold <= 1.0)) {
    throw MakeInputError(
        "detector.score_threshold",
        "is " + std::to_string(config.score_threshold) + ", expected a value in [0, 1]");
  }
  if (!(config.nms_iou > 0.0 && config.nms_iou <= 1.0)) {
    throw MakeInputError("detector.nms_iou",
                         "is " + std::to_string(config.nms_iou) + ", expected a value in (0, 1]");
  }
  if (config.ensemble_below < 0) {
    throw MakeInputError("detector.ensemble_below",
                         "is " + std::to_string(config.ensemble_below) +
                             ", expected 0 (both detectors on every view) or a count >= 1");
  }
  if (config.backend == "yolox") {
    return std::make_unique<YoloxDetector>(paths.yolox_onnx, paths.yolox_classes, config,
                                           inference);
  }
  if (config.backend == "darknet") {
    return std::make_unique<DarknetDetector>(paths.darknet_cfg, paths.darknet_weights,
                                             paths.darknet_classes, config);
  }
  if (config.backend == "picodet") {
    return std::make_unique<PicodetDetector>(paths.picodet_onnx, paths.picodet_opencv_onnx,
                                             paths.picodet_classes, config, inference);
  }
  if (config.backend == "ensemble") {
    return std::make_unique<EnsembleDetector>(
        std::make_unique<YoloxDetector>(paths.yolox_onnx, paths.yolox_classes, config, inference),
        "picodet",
        [paths, config, inference]() -> std::unique_ptr<Detector> {
          return std::make_unique<PicodetDetector>(paths.picodet_onnx, paths.picodet_opencv_onnx,
                                                   paths.picodet_classes, config, inference);
        },
        config);
  }
  if (config.backend == "file") return std::make_unique<FileDetector>(config);
  throw MakeInputError("detector.backend",
                       "unknown backend '" + config.backend +
                           "', expected one of: yolox, picodet, ensemble, darknet, file");
}

namespace detail {

void RequireReadableFile(const std::string& path, const std::string& what) {
  if (path.empty()) throw MakeInputError(what, "no file given");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MakeInputError(path, "cannot open " + what);
}

void RequireBgrImage(const cv::Mat& bgr, const std::string& image_name) {
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw MakeInputError(image_name.empty() ? std::string("image") : image_name,
                         "detector needs a non-empty 8-bit 3-channel BGR image");
  }
}

std::vector<std::string> ReadClassNames(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MakeInputError(path, "cannot open class-name list (one name per line expected)");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    names.push_back(line);
  }
  while (!names.empty() && names.back().empty()) names.pop_back();
  if (names.empty()) throw MakeInputError(path, "class-name list is empty");
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) {
      throw MakeInputError(path, "line " + std::to_string(i + 1) + " is empty, expected a name");
    }
  }
  return names;
}

std::vector<Detection> NonMaxSuppressionPerClass(const std::vector<Detection>& candidates,
                                                 double nms_iou) {
  std::vector<size_t> order(candidates.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  // Stable so that equal scores keep input order: the output is deterministic.
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return candidates[a].score > candidates[b].score; });
  std::vector<Detection> kept;
  for (size_t i : order) {
    const Detection& d = candidates[i];
    bool suppressed = false;
    for (const Detection& k : kept) {
      if (k.class_id != d.class_id || k.label != d.label) continue;
      const float inter = (k.box & d.box).area();
      const float uni = k.box.area() + d.box.area() - inter;
      if (uni > 0.0f && inter / uni > nms_iou) {
        suppressed = true;
        break;
      }
    }
    if (!suppressed) kept.push_back(d);
  }
  return kept;
}

std::string ImageStem(const std::string& image_name) {
  const size_t slash = image_name.find_last_of("/\\");
  std::string file = slash == std::string::npos ? image_name : image_name.substr(slash + 1);
  const size_t dot = file.find_last_of('.');
  if (dot != std::string::npos && dot > 0) file = file.substr(0, dot);
  return file;
}

cv::Mat LetterboxTopLeft(const cv::Mat& bgr, int size, double* r) {
  const double scale =
      std::min(static_cast<double>(size) / bgr.rows, static_cast<double>(size) / bgr.cols);
  // At least 1 pixel: a 1x1000 image scales to 0.4 x 416, which cv::resize refuses.
  const int w = std::clamp(static_cast<int>(std::lround(bgr.cols * scale)), 1, size);
  const int h = std::clamp(static_cast<int>(std::lround(bgr.rows * scale)), 1, size);
  cv::Mat canvas(size, size, CV_8UC3, cv::Scalar(114, 114, 114));
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(w, h), 0, 0, cv::INTER_LINEAR);
  resized.copyTo(canvas(cv::Rect(0, 0, w, h)));
  *r = scale;
  return canvas;
}

}  // namespace detail
}  // namespace zeroreg
