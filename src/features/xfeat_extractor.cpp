#include "features/xfeat_extractor.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>

#include "inference/image_tensor.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Bilinear sample of a C x H x W float blob (contiguous) at continuous cell coordinates (u, v),
// clamped at the borders.
void SampleBilinear(const float* blob, int channels, int height, int width, float u, float v,
                    float* out) {
  u = std::clamp(u, 0.0f, static_cast<float>(width - 1));
  v = std::clamp(v, 0.0f, static_cast<float>(height - 1));
  const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float ax = u - static_cast<float>(x0), ay = v - static_cast<float>(y0);
  const size_t plane = static_cast<size_t>(height) * width;
  for (int c = 0; c < channels; ++c) {
    const float* p = blob + c * plane;
    const float top = p[y0 * width + x0] * (1 - ax) + p[y0 * width + x1] * ax;
    const float bottom = p[y1 * width + x0] * (1 - ax) + p[y1 * width + x1] * ax;
    out[c] = top * (1 - ay) + bottom * ay;
  }
}

}  // namespace

XFeatExtractor::XFeatExtractor(const std::string& model_path, const FeatureConfig& config,
                               const InferenceConfig& inference, XFeatInput input)
    : config_(config),
      input_(input),
      square_input_(UsesSquareInput(inference, input)),
      model_(LoadOnnxModel(model_path,
                           square_input_ ? "XFeat ONNX model (expected xfeat_640x640.onnx from "
                                           "models/xfeat)"
                                         : "XFeat ONNX model (expected xfeat_any_size.onnx, made "
                                           "by scripts/fetch-assets.sh)",
                           inference)) {}

bool XFeatExtractor::UsesSquareInput(const InferenceConfig& inference, const XFeatInput& input) {
  return input.square || ResolveEngine(inference) == InferenceEngine::kOpenCv;
}

std::string XFeatExtractor::ModelFile(const InferenceConfig& inference, const XFeatInput& input) {
  return UsesSquareInput(inference, input) ? "xfeat/xfeat_640x640.onnx"
                                           : "xfeat/xfeat_any_size.onnx";
}

cv::Size XFeatExtractor::InputSize(const cv::Size& image, bool square_input) {
  if (square_input) return {kInputSize, kInputSize};
  // The scaled image (longer side 640 px) rounded up to multiples of 32: the backbone halves the
  // resolution five times, and upstream XFeat sizes its input the same way.
  const double scale = std::min(static_cast<double>(kInputSize) / image.width,
                                static_cast<double>(kInputSize) / image.height);
  const auto round_up = [&](int pixels) {
    const int scaled = std::min(kInputSize, static_cast<int>(std::lround(pixels * scale)));
    return (scaled + kSizeMultiple - 1) / kSizeMultiple * kSizeMultiple;
  };
  return {round_up(image.width), round_up(image.height)};
}

ImageFeatures XFeatExtractor::Extract(const cv::Mat& bgr) const {
  const cv::Size input = InputSize(bgr.size(), square_input_);
  const int n_x = input.width, n_y = input.height;
  const int cells_x = n_x / kCell, cells_y = n_y / kCell;
  // The image is scaled uniformly so that its longer side is 640 px (a 640x480 frame is not
  // scaled at all) and the rest of the input is filled with the image's mean colour: stretching
  // it instead distorted 540x360 HoloLens frames by 1.19x / 1.78x, so the
  // same surface looked different in two views at different angles. The flat fill gives no
  // keypoints; any found within a cell of it are dropped below.
  const double scale = std::min(static_cast<double>(kInputSize) / bgr.cols,
                                static_cast<double>(kInputSize) / bgr.rows);
  const int width = std::min(n_x, static_cast<int>(std::lround(bgr.cols * scale)));
  const int height = std::min(n_y, static_cast<int>(std::lround(bgr.rows * scale)));
  cv::Mat padded(n_y, n_x, CV_8UC3, cv::mean(bgr));
  if (width == bgr.cols && height == bgr.rows) {
    bgr.copyTo(padded(cv::Rect(0, 0, width, height)));
  } else {
    // Linear when enlarging, area averaging when shrinking (no aliasing).
    const int interpolation =
        width >= bgr.cols && height >= bgr.rows ? cv::INTER_LINEAR : cv::INTER_AREA;
    cv::resize(bgr, padded(cv::Rect(0, 0, width, height)), cv::Size(width, height), 0, 0,
               interpolation);
  }
  const std::vector<float> blob = ImagePlanes(padded, 1.0 / 255.0, /*swap_rb=*/true);
  std::vector<TensorInput> inputs = {{"input", {1, 3, n_y, n_x}, blob.data()}};
  // The any-size model multiplies the normalised grey image by `contrast`
  // (scripts/rewrite_onnx_xfeat.py). On the square the fill (the image's mean) diluted the grey
  // variance by the fill's share; the same factor here gives the features of the square.
  const float contrast =
      input_.square_contrast
          ? static_cast<float>(std::sqrt(static_cast<double>(kInputSize) * kInputSize /
                                         (static_cast<double>(n_x) * n_y)))
          : 1.0f;
  if (!square_input_) inputs.push_back({"contrast", {1}, &contrast});
  const std::vector<Tensor> outputs = model_->Run(inputs, {"output", "1266", "266"});
  const float* descriptor_map = outputs[0].data.data();  // D x H/8 x W/8
  const float* logits = outputs[1].data.data();          // 65 x H/8 x W/8
  const float* reliability = outputs[2].data.data();     // 1 x H/8 x W/8, sigmoid applied
  const size_t plane = static_cast<size_t>(cells_y) * cells_x;
  const int descriptor_dim =
      outputs[0].shape.size() == 4 ? static_cast<int>(outputs[0].shape[1]) : 0;
  if (descriptor_dim < 1 || outputs[0].data.size() != descriptor_dim * plane ||
      outputs[1].data.size() != 65 * plane || outputs[2].data.size() != plane) {
    throw MakeInputError("XFeat ONNX model", "outputs are not 1xDx" + std::to_string(cells_y) +
                                                 "x" + std::to_string(cells_x) +
                                                 ", 1x65x.., 1x1x.. for a " + std::to_string(n_x) +
                                                 "x" + std::to_string(n_y) + " input");
  }

  // Softmax over the 65 channels of each cell; channel c < 64 is pixel (c / 8, c % 8) of the cell.
  cv::Mat heat(n_y, n_x, CV_32F);
  for (int cy = 0; cy < cells_y; ++cy) {
    for (int cx = 0; cx < cells_x; ++cx) {
      const size_t cell = static_cast<size_t>(cy) * cells_x + cx;
      float max_logit = -1e30f;
      for (int c = 0; c < 65; ++c) max_logit = std::max(max_logit, logits[c * plane + cell]);
      float sum = 0;
      float e[65];
      for (int c = 0; c < 65; ++c) sum += (e[c] = std::exp(logits[c * plane + cell] - max_logit));
      for (int c = 0; c < 64; ++c) {
        heat.at<float>(cy * kCell + c / kCell, cx * kCell + c % kCell) = e[c] / sum;
      }
    }
  }

  // 5x5 non-maximum suppression and the detection threshold.
  cv::Mat local_max;
  cv::dilate(heat, local_max, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
  struct Candidate {
    float x, y, score;
  };
  std::vector<Candidate> candidates;
  const float threshold = static_cast<float>(config_.xfeat_detection_threshold);
  const int x_end = width < n_x ? width - kCell : n_x;
  const int y_end = height < n_y ? height - kCell : n_y;
  for (int y = 0; y < n_y; ++y) {
    const float* h = heat.ptr<float>(y);
    const float* m = local_max.ptr<float>(y);
    for (int x = 0; x < n_x; ++x) {
      if (x >= x_end || y >= y_end) break;  // the fill and its border
      if (h[x] > threshold && h[x] >= m[x]) {
        // Cell coordinates of pixel centre (x, y) with align_corners = false.
        const float u = (static_cast<float>(x) + 0.5f) / kCell - 0.5f;
        const float v = (static_cast<float>(y) + 0.5f) / kCell - 0.5f;
        float r = 0;
        SampleBilinear(reliability, 1, cells_y, cells_x, u, v, &r);
        candidates.push_back({static_cast<float>(x), static_cast<float>(y), h[x] * r});
      }
    }
  }
  // Strongest first; ties broken by position so the order never depends on anything else.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  if (static_cast<int>(candidates.size()) > config_.max_keypoints) {
    candidates.resize(config_.max_keypoints);
  }

  ImageFeatures out;
  out.descriptors.resize(static_cast<Eigen::Index>(candidates.size()), descriptor_dim);
  const float sx = static_cast<float>(bgr.cols) / width, sy = static_cast<float>(bgr.rows) / height;
  std::vector<float> d(descriptor_dim);
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Candidate& c = candidates[i];
    SampleBilinear(descriptor_map, descriptor_dim, cells_y, cells_x, (c.x + 0.5f) / kCell - 0.5f,
                   (c.y + 0.5f) / kCell - 0.5f, d.data());
    float norm = 0;
    for (float value : d) norm += value * value;
    norm = std::max(std::sqrt(norm), 1e-12f);
    for (int k = 0; k < descriptor_dim; ++k) {
      out.descriptors(static_cast<Eigen::Index>(i), k) = d[k] / norm;
    }
    // Back to the input image's pixels (pixel centres map to pixel centres).
    out.keypoints.emplace_back((c.x + 0.5f) * sx - 0.5f, (c.y + 0.5f) * sy - 0.5f);
    out.scores.push_back(c.score);
  }
  return out;
}

}  // namespace zeroreg
