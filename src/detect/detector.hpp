// Object detection (paper §3.2 "Object Detection and Segmentation"): boxes and category labels per
// view. The paper uses Florence-2, a transformer OpenCV's DNN cannot run; the backends here are
// small COCO-80 CNNs plus a file reader so that detections made elsewhere can be fed in.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg {

struct Detection {
  cv::Rect2f box;      // pixels in the original image, (x, y) = top-left corner
  std::string label;   // category name, COCO spelling for the built-in backends ("dining table")
  float score = 0.0f;  // confidence in [0, 1]
  int class_id = -1;   // row in the backend's class list; -1 when unknown (file backend)
};

// Model files, already resolved and verified by the caller (the pipeline); only those of the
// chosen backend are read.
struct DetectorModelPaths {
  std::string yolox_onnx;           // yolox_nano_coco/yolox_nano.onnx
  std::string yolox_classes;        // yolox_nano_coco/coco_classes.txt
  std::string darknet_cfg;          // yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.cfg
  std::string darknet_weights;      // yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.weights
  std::string darknet_classes;      // yolo_fastest_1.1_xl_coco/coco_classes.txt
  std::string picodet_onnx;         // picodet_s_416_coco/picodet_s_416_coco.onnx (ONNX Runtime)
  std::string picodet_opencv_onnx;  // picodet_s_416_coco/picodet_s_416_coco.opencv.onnx (OpenCV)
  std::string picodet_classes;      // picodet_s_416_coco/coco.names (VOC spellings, mapped on load)
};

class Detector {
 public:
  virtual ~Detector() = default;
  // `bgr` is CV_8UC3. `image_name` is the image's file name (or any name whose stem identifies it);
  // only the file backend uses it. Results are sorted by decreasing score.
  virtual std::vector<Detection> Detect(const cv::Mat& bgr, const std::string& image_name) = 0;
  virtual std::string name() const = 0;
};

// Throws InputError for an unknown backend, or a missing / corrupt model or class-list file.
// ONNX detectors run on the engine of `inference` (default: auto).
std::unique_ptr<Detector> MakeDetector(const DetectorConfig& config,
                                       const DetectorModelPaths& paths,
                                       const InferenceConfig& inference = {});

namespace detail {

// Throws InputError naming `path` (or `what` when path is empty) if the file cannot be opened.
void RequireReadableFile(const std::string& path, const std::string& what);
// Throws InputError naming the image unless `bgr` is a non-empty CV_8UC3 image.
void RequireBgrImage(const cv::Mat& bgr, const std::string& image_name);

// One class name per line; blank trailing lines ignored. Throws InputError if unreadable/empty.
std::vector<std::string> ReadClassNames(const std::string& path);

// Per-class NMS on candidates, then threshold already applied by the caller; returns the kept
// detections sorted by decreasing score.
std::vector<Detection> NonMaxSuppressionPerClass(const std::vector<Detection>& candidates,
                                                 double nms_iou);

// "dir/frame-000000.color.jpg" -> "frame-000000.color" (file name without its last extension).
std::string ImageStem(const std::string& image_name);

// Letterbox used by YOLOX (MANIFEST): scale r = min(S/h, S/w), resize to (round(w r), round(h r)),
// paste at the top-left of an S x S canvas filled with 114. Returns the canvas; r is written out.
cv::Mat LetterboxTopLeft(const cv::Mat& bgr, int size, double* r);

}  // namespace detail

}  // namespace zeroreg
