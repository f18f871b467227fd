// The concrete detectors behind MakeDetector. Each takes file paths (already resolved and verified
// by the pipeline) and throws InputError naming the file when it cannot be loaded.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <opencv2/dnn.hpp>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "inference/onnx_model.hpp"

namespace zeroreg {

// YOLOX-Nano, COCO-80, ONNX (models/yolox_nano_coco/MANIFEST.md): 416x416 BGR 0-255 input,
// top-left letterbox on a 114 canvas, anchor-free grid decode over strides 8/16/32. Runs on the
// engine of inference.engine (src/inference/onnx_model.hpp).
class YoloxDetector : public Detector {
 public:
  YoloxDetector(const std::string& onnx_path, const std::string& classes_path,
                const DetectorConfig& config, const InferenceConfig& inference = {});
  std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) override;
  std::string name() const override { return "yolox"; }

  static constexpr int kInputSize = 416;

 private:
  std::vector<std::string> classes_;
  std::unique_ptr<OnnxModel> model_;  // thread-safe Run: one Pipeline, many threads
  DetectorConfig config_;
  std::string onnx_path_;
};

// PP-PicoDet-S 416, COCO-80, ONNX (models/picodet_s_416_coco/MANIFEST.md), run on the engine of
// inference.engine: ONNX Runtime loads the verbatim export (`onnx_path`), OpenCV DNN the
// Clip-rewritten copy (`opencv_onnx_path`, scripts/rewrite_onnx_clip.py); only the path of the
// chosen engine is read. Pre- and post-processing live in detect/picodet_codec.hpp and are shared
// by both engines. Labels are reported in the COCO-2017 spellings (CocoSpelling), class_id is the
// row of the COCO-80 list (same order as YOLOX's).
class PicodetDetector : public Detector {
 public:
  PicodetDetector(const std::string& onnx_path, const std::string& opencv_onnx_path,
                  const std::string& classes_path, const DetectorConfig& config,
                  const InferenceConfig& inference = {});
  std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) override;
  std::string name() const override { return "picodet"; }

 private:
  std::unique_ptr<OnnxModel> model_;       // thread-safe Run: one Pipeline, many threads
  std::vector<std::string> output_names_;  // all 8, told apart by shape in PicodetDecode
  std::vector<std::string> classes_;
  DetectorConfig config_;
  std::string onnx_path_;  // the file of the chosen engine
};

// Several detectors on the same image (backend "ensemble": YOLOX-Nano, then PicoDet): their
// detections are pooled and per-class NMS (config.nms_iou) keeps the best box of each object, so
// an object both find is reported once. The members' labels must share one spelling (COCO-2017).
// With config.ensemble_below > 0 the second detector runs only on images where the first found
// fewer than that many objects, and is built (its model loaded) on the first image that needs it,
// so a run whose images never need it never loads it.
class EnsembleDetector : public Detector {
 public:
  using Factory = std::function<std::unique_ptr<Detector>()>;
  // `first` runs on every image; `make_second` builds the second detector, named `second_name`,
  // at once (ensemble_below = 0) or on first use.
  EnsembleDetector(std::unique_ptr<Detector> first, std::string second_name, Factory make_second,
                   const DetectorConfig& config);
  std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) override;
  std::string name() const override;

 private:
  Detector& Second();

  std::unique_ptr<Detector> first_;  // thread-safe on its own, as the second
  std::string second_name_;
  Factory make_second_;
  std::once_flag second_built_;
  std::unique_ptr<Detector> second_;
  DetectorConfig config_;
};

// Yolo-Fastest-1.1-xl, COCO-80, Darknet cfg + weights (models/yolo_fastest_1.1_xl_coco): 320x320
// RGB /255 plain resize; OpenCV's region layer already multiplies class scores by objectness.
class DarknetDetector : public Detector {
 public:
  DarknetDetector(const std::string& cfg_path, const std::string& weights_path,
                  const std::string& classes_path, const DetectorConfig& config);
  std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) override;
  std::string name() const override { return "darknet"; }

  static constexpr int kInputSize = 320;

 private:
  // Throws InputError naming the file if it holds fewer parameters than the network needs.
  void CheckWeightsSize(const std::string& weights_path) const;

  cv::dnn::Net net_;
  std::mutex net_mutex_;  // as YoloxDetector's
  std::vector<std::string> classes_;
  std::vector<std::string> output_names_;
  DetectorConfig config_;
  std::string weights_path_;
};

// Precomputed detections: <detections_dir>/<image stem>.json (format in docs/PERCEPTION.md).
// Lets users run detectors OpenCV cannot (Florence-2, the paper's choice) and feed the output in.
class FileDetector : public Detector {
 public:
  explicit FileDetector(const DetectorConfig& config);
  std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) override;
  std::string name() const override { return "file"; }

  // Path of the JSON file read for `image_name`.
  std::string PathFor(const std::string& image_name) const;

 private:
  DetectorConfig config_;
};

}  // namespace zeroreg
