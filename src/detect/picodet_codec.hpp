// PP-PicoDet-S 416 COCO pre- and post-processing (models/picodet_s_416_coco/MANIFEST.md), kept
// apart from the forward pass so that any inference engine can run the network in between:
//   PicodetInput(image) -> blob -> [engine forward] -> 8 output tensors -> PicodetDecode.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg::detail {

constexpr int kPicodetInputSize = 416;
constexpr int kPicodetBins = 8;  // GFL: each box side is a distribution over 8 bins
constexpr int kPicodetStrides[4] = {8, 16, 32, 64};

// Where the image sits in the 416 x 416 input: input = image * scale + (pad_x, pad_y).
struct PicodetLetterbox {
  double scale = 1.0;
  int pad_x = 0, pad_y = 0;
};

// 1 x 3 x 416 x 416 float32 blob: BGR, the long side resized (INTER_AREA) to 416, the short side
// padded symmetrically with 0 (top = (416 - nh) / 2) before the (v - mean) / std normalisation
// with mean (103.53, 116.28, 123.675), std (57.375, 57.12, 58.395). `bgr` is CV_8UC3.
cv::Mat PicodetInput(const cv::Mat& bgr, PicodetLetterbox* letterbox);

// Decodes the 8 output tensors, in any order (identified by shape): per stride s, class scores
// [1, n_s, C] (already sigmoid) and box distributions [1, n_s, 4 x 8] (left, top, right, bottom),
// n_s = ceil(416 / s)^2. Per cell the best class is kept when its score >= score_threshold; its box
// is (cx - l, cy - t, cx + r, cy + b) with the cell centre (j s + (s - 1) / 2, i s + (s - 1) / 2)
// and each side the expectation of the softmax over the bins times s; the box is mapped back to
// the image, clipped to it, and per-class NMS (nms_iou) gives the result, by decreasing score.
// Labels are classes[k]. Throws InputError naming `model` when the tensors do not fit.
std::vector<Detection> PicodetDecode(const std::vector<cv::Mat>& outputs,
                                     const PicodetLetterbox& letterbox, cv::Size image_size,
                                     const std::vector<std::string>& classes,
                                     const DetectorConfig& config, const std::string& model);

}  // namespace zeroreg::detail
