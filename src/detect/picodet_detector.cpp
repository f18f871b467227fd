#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "detect/backends.hpp"
#include "detect/picodet_codec.hpp"
#include "semantics/label_aliases.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace detail {

cv::Mat PicodetInput(const cv::Mat& bgr, PicodetLetterbox* letterbox) {
  const int size = kPicodetInputSize;
  const double scale =
      std::min(static_cast<double>(size) / bgr.rows, static_cast<double>(size) / bgr.cols);
  const int w = std::clamp(static_cast<int>(std::lround(bgr.cols * scale)), 1, size);
  const int h = std::clamp(static_cast<int>(std::lround(bgr.rows * scale)), 1, size);
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  const int top = (size - h) / 2, left = (size - w) / 2;
  cv::Mat canvas;
  cv::copyMakeBorder(resized, canvas, top, size - h - top, left, size - w - left,
                     cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0));
  cv::Mat normalised;
  canvas.convertTo(normalised, CV_32FC3);
  normalised -= cv::Scalar(103.53, 116.28, 123.675);
  cv::divide(normalised, cv::Scalar(57.375, 57.12, 58.395), normalised);
  letterbox->scale = scale;
  letterbox->pad_x = left;
  letterbox->pad_y = top;
  return cv::dnn::blobFromImage(normalised, 1.0, cv::Size(), cv::Scalar(), /*swapRB=*/false,
                                /*crop=*/false, CV_32F);
}

namespace {

// Cells along one side of the stride-s grid: the export pads odd sizes up (416 / 64 -> 7).
int GridSide(int stride) { return (kPicodetInputSize + stride - 1) / stride; }

// Rows x columns of a [1, n, c] (or [n, c]) tensor; {0, 0} for anything else.
std::pair<int, int> RowsCols(const cv::Mat& m) {
  if (m.dims == 3 && m.size[0] == 1) return {m.size[1], m.size[2]};
  if (m.dims == 2) return {m.rows, m.cols};
  return {0, 0};
}

// Expected distance of one box side: softmax over the bins, then sum_k k p_k.
double SideDistance(const float* logits) {
  float peak = logits[0];
  for (int k = 1; k < kPicodetBins; ++k) peak = std::max(peak, logits[k]);
  double sum = 0.0, weighted = 0.0;
  for (int k = 0; k < kPicodetBins; ++k) {
    const double e = std::exp(static_cast<double>(logits[k] - peak));
    sum += e;
    weighted += k * e;
  }
  return weighted / sum;
}

}  // namespace

std::vector<Detection> PicodetDecode(const std::vector<cv::Mat>& outputs,
                                     const PicodetLetterbox& letterbox, cv::Size image_size,
                                     const std::vector<std::string>& classes,
                                     const DetectorConfig& config, const std::string& model) {
  const int num_classes = static_cast<int>(classes.size());
  const int box_cols = 4 * kPicodetBins;
  if (num_classes == box_cols) {
    // Score and box tensors are told apart by their width.
    throw MakeInputError(model, "cannot tell score from box tensors with 32 classes");
  }
  std::vector<const cv::Mat*> scores(4, nullptr), boxes(4, nullptr);
  for (const cv::Mat& m : outputs) {
    const auto [rows, cols] = RowsCols(m);
    for (int s = 0; s < 4; ++s) {
      const int side = GridSide(kPicodetStrides[s]);
      if (rows != side * side || m.type() != CV_32F) continue;
      if (cols == num_classes) scores[s] = &m;
      if (cols == box_cols) boxes[s] = &m;
    }
  }
  for (int s = 0; s < 4; ++s) {
    if (scores[s] == nullptr || boxes[s] == nullptr) {
      const int side = GridSide(kPicodetStrides[s]);
      throw MakeInputError(model, "no output pair [1, " + std::to_string(side * side) + ", " +
                                      std::to_string(num_classes) + "] + [1, " +
                                      std::to_string(side * side) + ", 32] for stride " +
                                      std::to_string(kPicodetStrides[s]) + " among " +
                                      std::to_string(outputs.size()) +
                                      " outputs (expected the PicoDet-S 416 COCO export)");
    }
  }
  const cv::Rect2f image_rect(0.0f, 0.0f, static_cast<float>(image_size.width),
                              static_cast<float>(image_size.height));
  std::vector<Detection> candidates;
  for (int s = 0; s < 4; ++s) {
    const int stride = kPicodetStrides[s], side = GridSide(stride);
    const float* score = scores[s]->ptr<float>();
    const float* dist = boxes[s]->ptr<float>();
    for (int cell = 0; cell < side * side; ++cell) {
      const float* p = score + static_cast<size_t>(cell) * num_classes;
      const int best = static_cast<int>(std::max_element(p, p + num_classes) - p);
      if (p[best] < config.score_threshold) continue;
      const double cx = (cell % side) * stride + 0.5 * (stride - 1);
      const double cy = (cell / side) * stride + 0.5 * (stride - 1);
      const float* d = dist + static_cast<size_t>(cell) * box_cols;
      const double l = SideDistance(d) * stride, t = SideDistance(d + kPicodetBins) * stride;
      const double r = SideDistance(d + 2 * kPicodetBins) * stride;
      const double b = SideDistance(d + 3 * kPicodetBins) * stride;
      const double x0 = (cx - l - letterbox.pad_x) / letterbox.scale;
      const double y0 = (cy - t - letterbox.pad_y) / letterbox.scale;
      const double x1 = (cx + r - letterbox.pad_x) / letterbox.scale;
      const double y1 = (cy + b - letterbox.pad_y) / letterbox.scale;
      cv::Rect2f box(static_cast<float>(x0), static_cast<float>(y0), static_cast<float>(x1 - x0),
                     static_cast<float>(y1 - y0));
      box &= image_rect;
      if (box.width <= 0.0f || box.height <= 0.0f) continue;
      candidates.push_back({box, classes[best], p[best], best});
    }
  }
  return NonMaxSuppressionPerClass(candidates, config.nms_iou);
}

}  // namespace detail

PicodetDetector::PicodetDetector(const std::string& onnx_path, const std::string& opencv_onnx_path,
                                 const std::string& classes_path, const DetectorConfig& config,
                                 const InferenceConfig& inference)
    : config_(config) {
  const InferenceEngine engine = ResolveEngine(inference);
  // OpenCV 4.6 DNN refuses the shipped export (opset-11 Clip with min/max as inputs); ONNX Runtime
  // loads it as is.
  const bool opencv = engine == InferenceEngine::kOpenCv;
  onnx_path_ = opencv ? opencv_onnx_path : onnx_path;
  detail::RequireReadableFile(onnx_path_, "PicoDet ONNX model");
  for (const std::string& name : detail::ReadClassNames(classes_path)) {
    classes_.push_back(CocoSpelling(name));  // "diningtable" -> "dining table", as YOLOX says
  }
  model_ = LoadOnnxModel(onnx_path_,
                         opencv ? "PicoDet ONNX model (expected the Clip-rewritten PicoDet export "
                                  "that scripts/fetch-assets.sh makes)"
                                : "PicoDet ONNX model (corrupt or not the PicoDet-S 416 export?)",
                         engine, inference.threads, inference.graph_cache);
  output_names_ = model_->OutputNames();
}

std::vector<Detection> PicodetDetector::Detect(const cv::Mat& bgr, const std::string& image_name) {
  detail::RequireBgrImage(bgr, image_name);
  detail::PicodetLetterbox letterbox;
  const cv::Mat blob = detail::PicodetInput(bgr, &letterbox);
  const std::vector<Tensor> tensors = model_->Run(
      {{"image", {1, 3, detail::kPicodetInputSize, detail::kPicodetInputSize}, blob.ptr<float>()}},
      output_names_);
  // Views on the tensors (alive until the decode returns), as PicodetDecode takes cv::Mat.
  std::vector<cv::Mat> outputs;
  for (const Tensor& t : tensors) {
    std::vector<int> dims(t.shape.begin(), t.shape.end());
    size_t count = 1;
    for (int d : dims) count *= static_cast<size_t>(std::max(d, 0));
    if (dims.empty() || dims.size() > 4 || count != t.data.size()) {
      outputs.emplace_back();  // not a [1, n, c] tensor: PicodetDecode names what is missing
      continue;
    }
    outputs.emplace_back(static_cast<int>(dims.size()), dims.data(), CV_32F,
                         const_cast<float*>(t.data.data()));
  }
  return detail::PicodetDecode(outputs, letterbox, bgr.size(), classes_, config_, onnx_path_);
}

EnsembleDetector::EnsembleDetector(std::unique_ptr<Detector> first, std::string second_name,
                                   Factory make_second, const DetectorConfig& config)
    : first_(std::move(first)),
      second_name_(std::move(second_name)),
      make_second_(std::move(make_second)),
      config_(config) {
  if (config_.ensemble_below <= 0) Second();
}

Detector& EnsembleDetector::Second() {
  std::call_once(second_built_, [&] { second_ = make_second_(); });
  return *second_;
}

std::vector<Detection> EnsembleDetector::Detect(const cv::Mat& bgr, const std::string& image_name) {
  // The members in their fixed order, each list by decreasing score: NMS's stable sort then breaks
  // score ties by member order, so the result does not depend on timing or threads.
  std::vector<Detection> all = first_->Detect(bgr, image_name);
  if (config_.ensemble_below > 0 && all.size() >= static_cast<size_t>(config_.ensemble_below)) {
    return all;  // enough: the first member's own (per-class NMS'd) list
  }
  std::vector<Detection> found = Second().Detect(bgr, image_name);
  all.insert(all.end(), found.begin(), found.end());
  return detail::NonMaxSuppressionPerClass(all, config_.nms_iou);
}

std::string EnsembleDetector::name() const {
  std::string n = "ensemble(" + first_->name() + "+" + second_name_;
  if (config_.ensemble_below > 0) n += " below " + std::to_string(config_.ensemble_below);
  return n + ")";
}

}  // namespace zeroreg
