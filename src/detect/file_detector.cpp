#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "detect/backends.hpp"
#include "io/shown.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Boxes may overhang the image by this much (pixels) and are then clipped: detectors that output
// float corners often give e.g. x2 = 640.3 for an object touching the border of a 640-wide image.
constexpr double kBorderTolerancePx = 1.0;

std::string FileName(const std::string& path) {
  const size_t slash = path.find_last_of("/\\");
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

FileDetector::FileDetector(const DetectorConfig& config) : config_(config) {
  if (config_.detections_dir.empty()) {
    throw MakeInputError(
        "detector.detections_dir",
        "is empty; the 'file' detector needs the folder of <image stem>.json files");
  }
}

std::string FileDetector::PathFor(const std::string& image_name) const {
  return config_.detections_dir + "/" + detail::ImageStem(image_name) + ".json";
}

std::vector<Detection> FileDetector::Detect(const cv::Mat& bgr, const std::string& image_name) {
  const std::string path = PathFor(image_name);
  if (bgr.empty()) throw MakeInputError(image_name, "image is empty");
  const nlohmann::json doc =
      detail::ReadJsonFile(path, "precomputed detections file for image '" + image_name +
                                     "' (expected <detections_dir>/<image stem>.json)");
  if (!doc.is_object()) throw MakeInputError(path, "top level must be a JSON object");
  if (doc.contains("image")) {
    // Optional, but when present it must name this image: guards against renamed/misfiled files.
    if (!doc["image"].is_string()) throw MakeInputError(path, "\"image\" must be a string");
    const std::string named = FileName(doc["image"].get<std::string>());
    if (named != FileName(image_name)) {
      throw MakeInputError(path, "\"image\" is '" + detail::ShownText(named) +
                                     "' but the file was read for '" + FileName(image_name) + "'");
    }
  }
  if (!doc.contains("detections") || !doc["detections"].is_array()) {
    throw MakeInputError(path, "missing key \"detections\" (expected an array of objects)");
  }
  const double W = bgr.cols, H = bgr.rows;
  std::vector<Detection> result;
  const auto& list = doc["detections"];
  if (config_.max_detections > 0 && list.size() > static_cast<size_t>(config_.max_detections)) {
    throw MakeInputError(path, "lists " + std::to_string(list.size()) +
                                   " detections, more than detector.max_detections (" +
                                   std::to_string(config_.max_detections) +
                                   "); every box is segmented, so this would take very long. "
                                   "Raise detector.max_detections (0 = no limit) to use them all");
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = path + " detections[" + std::to_string(i) + "]";
    const auto& d = list[i];
    if (!d.is_object()) throw MakeInputError(where, "must be an object");
    if (!d.contains("box") || !d["box"].is_array() || d["box"].size() != 4) {
      throw MakeInputError(where, "missing or bad key \"box\" (expected [x1, y1, x2, y2] pixels)");
    }
    double c[4];
    for (int k = 0; k < 4; ++k) {
      if (!d["box"][k].is_number() || !std::isfinite(d["box"][k].get<double>())) {
        throw MakeInputError(where, "\"box\" values must be finite numbers");
      }
      c[k] = d["box"][k].get<double>();
    }
    if (!(c[2] > c[0] && c[3] > c[1])) {
      throw MakeInputError(where, "\"box\" needs x2 > x1 and y2 > y1, got [" +
                                      detail::ShownNumber(c[0]) + ", " + detail::ShownNumber(c[1]) +
                                      ", " + detail::ShownNumber(c[2]) + ", " +
                                      detail::ShownNumber(c[3]) + "]");
    }
    const double t = kBorderTolerancePx;
    if (c[0] < -t || c[1] < -t || c[2] > W + t || c[3] > H + t) {
      throw MakeInputError(where, "\"box\" [" + detail::ShownNumber(c[0]) + ", " +
                                      detail::ShownNumber(c[1]) + ", " + detail::ShownNumber(c[2]) +
                                      ", " + detail::ShownNumber(c[3]) + "] lies outside the " +
                                      std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                                      " image");
    }
    if (!d.contains("label") || !d["label"].is_string() || d["label"].get<std::string>().empty()) {
      throw MakeInputError(where, "missing key \"label\" (expected a non-empty string)");
    }
    double score = 1.0;  // optional: Florence-2 and similar give no score
    if (d.contains("score")) {
      if (!d["score"].is_number()) throw MakeInputError(where, "\"score\" must be a number");
      score = d["score"].get<double>();
      if (!(score >= 0.0 && score <= 1.0)) {
        throw MakeInputError(
            where, "\"score\" is " + detail::ShownNumber(score) + ", expected a value in [0, 1]");
      }
    }
    if (score < config_.score_threshold) continue;
    const double x1 = std::max(0.0, c[0]), y1 = std::max(0.0, c[1]);
    const double x2 = std::min(W, c[2]), y2 = std::min(H, c[3]);
    Detection det;
    det.box = cv::Rect2f(static_cast<float>(x1), static_cast<float>(y1),
                         static_cast<float>(x2 - x1), static_cast<float>(y2 - y1));
    det.label = d["label"].get<std::string>();
    det.score = static_cast<float>(score);
    det.class_id = -1;
    result.push_back(det);
  }
  // Taken as given (no NMS: the producer decided), only ordered like the other backends.
  std::stable_sort(result.begin(), result.end(),
                   [](const Detection& a, const Detection& b) { return a.score > b.score; });
  return result;
}

}  // namespace zeroreg
