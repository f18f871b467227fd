#include "objects/appearance.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "segment/segmenter.hpp"

namespace zeroreg {
namespace {

constexpr int kHueBins = 12, kSatBins = 3, kGreyBins = 4;
// Below this saturation (OpenCV's 0-255 scale) hue is dominated by sensor noise and JPEG chroma
// subsampling: such pixels are binned by value instead.
constexpr int kMinChromaticSaturation = 48;

}  // namespace

Appearance ColourAppearance(const cv::Mat& bgr, const cv::Mat& mask) {
  Appearance out;
  if (bgr.empty() || mask.size() != bgr.size() || bgr.type() != CV_8UC3 || mask.type() != CV_8UC1) {
    return out;
  }
  // Only the mask's bounding box is converted: masks cover a few percent of the image.
  const cv::Rect roi = cv::boundingRect(mask);
  if (roi.area() == 0) return out;
  cv::Mat hsv;
  cv::cvtColor(bgr(roi), hsv, cv::COLOR_BGR2HSV);  // H in [0, 180), S and V in [0, 255]
  std::vector<double> counts(kHueBins * kSatBins + kGreyBins, 0.0);
  double total = 0.0;
  for (int y = 0; y < roi.height; ++y) {
    const uchar* m = mask.ptr<uchar>(roi.y + y) + roi.x;
    const cv::Vec3b* p = hsv.ptr<cv::Vec3b>(y);
    for (int x = 0; x < roi.width; ++x) {
      if (m[x] == 0) continue;
      const int h = p[x][0], s = p[x][1], v = p[x][2];
      int bin;
      if (s >= kMinChromaticSaturation) {
        const int hb = std::min(kHueBins - 1, h * kHueBins / 180);
        const int sb = std::min(kSatBins - 1, (s - kMinChromaticSaturation) * kSatBins /
                                                  (256 - kMinChromaticSaturation));
        bin = hb * kSatBins + sb;
      } else {
        bin = kHueBins * kSatBins + std::min(kGreyBins - 1, v * kGreyBins / 256);
      }
      counts[bin] += 1.0;
      total += 1.0;
    }
  }
  if (total == 0.0) return out;
  out.kind = kColourHistogramKind;
  out.values.resize(counts.size());
  for (size_t i = 0; i < counts.size(); ++i) {
    out.values[i] = static_cast<float>(std::sqrt(counts[i] / total));
  }
  return out;
}

EmbeddingPooler::EmbeddingPooler(const ImageEmbedding& embedding, cv::Size image_size)
    : embedding_(embedding), image_size_(image_size) {
  if (embedding_.empty() || image_size_.area() == 0) return;
  view_mean_ = WeightedMean(CellWeights(cv::Mat(image_size_, CV_8UC1, cv::Scalar(255))));
}

std::vector<double> EmbeddingPooler::CellWeights(const cv::Mat& mask) const {
  std::vector<double> weights(static_cast<size_t>(embedding_.rows) * embedding_.cols, 0.0);
  const cv::Rect roi = cv::boundingRect(mask);
  const double per_cell = embedding_.pixels_per_cell;
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const uchar* m = mask.ptr<uchar>(y);
    const int row = std::min(embedding_.rows - 1, static_cast<int>((y + 0.5) / per_cell));
    for (int x = roi.x; x < roi.x + roi.width; ++x) {
      if (m[x] == 0) continue;
      const int col = std::min(embedding_.cols - 1, static_cast<int>((x + 0.5) / per_cell));
      weights[static_cast<size_t>(row) * embedding_.cols + col] += 1.0;
    }
  }
  return weights;
}

std::vector<double> EmbeddingPooler::WeightedMean(const std::vector<double>& cell_weights) const {
  const size_t cells = cell_weights.size();
  std::vector<size_t> used;
  double total = 0.0;
  for (size_t cell = 0; cell < cells; ++cell) {
    if (cell_weights[cell] == 0.0) continue;
    used.push_back(cell);
    total += cell_weights[cell];
  }
  if (total == 0.0) return {};
  // Channel-major layout (channel c of cell k is data[c * cells + k]): one channel at a time
  // reads each channel's plane in order.
  std::vector<double> mean(embedding_.channels, 0.0);
  for (int c = 0; c < embedding_.channels; ++c) {
    const float* plane = embedding_.data.data() + static_cast<size_t>(c) * cells;
    double sum = 0.0;
    for (size_t cell : used) sum += cell_weights[cell] * plane[cell];
    mean[c] = sum / total;
  }
  return mean;
}

Appearance EmbeddingPooler::Pool(const cv::Mat& mask) const {
  Appearance out;
  if (view_mean_.empty() || mask.size() != image_size_ || mask.type() != CV_8UC1) return out;
  std::vector<double> pooled = WeightedMean(CellWeights(mask));
  if (pooled.empty()) return out;
  double norm = 0.0;
  for (size_t c = 0; c < pooled.size(); ++c) {
    pooled[c] -= view_mean_[c];
    norm += pooled[c] * pooled[c];
  }
  norm = std::sqrt(norm);
  if (!(norm > 0.0)) return out;  // the mask covers the whole image: nothing sets it apart
  out.kind = kSamEmbeddingKind;
  out.values.resize(pooled.size());
  for (size_t c = 0; c < pooled.size(); ++c) out.values[c] = static_cast<float>(pooled[c] / norm);
  return out;
}

bool Comparable(const Appearance& a, const Appearance& b) {
  return !a.empty() && !b.empty() && a.kind == b.kind && a.values.size() == b.values.size();
}

double AppearanceSimilarity(const Appearance& a, const Appearance& b) {
  if (!Comparable(a, b)) return 0.0;
  double dot = 0.0, na = 0.0, nb = 0.0;
  for (size_t i = 0; i < a.values.size(); ++i) {
    dot += static_cast<double>(a.values[i]) * b.values[i];
    na += static_cast<double>(a.values[i]) * a.values[i];
    nb += static_cast<double>(b.values[i]) * b.values[i];
  }
  return na > 0.0 && nb > 0.0 ? dot / std::sqrt(na * nb) : 0.0;
}

Appearance MeanAppearance(const std::vector<const Appearance*>& views) {
  Appearance out;
  std::vector<double> sum;
  for (const Appearance* a : views) {
    if (a == nullptr || a->empty()) continue;
    if (out.kind.empty()) {
      out.kind = a->kind;
      sum.assign(a->values.size(), 0.0);
    }
    if (a->kind != out.kind || a->values.size() != sum.size()) continue;
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += a->values[i];
  }
  double norm = 0.0;
  for (double v : sum) norm += v * v;
  norm = std::sqrt(norm);
  if (norm == 0.0) return Appearance{};
  out.values.resize(sum.size());
  for (size_t i = 0; i < sum.size(); ++i) out.values[i] = static_cast<float>(sum[i] / norm);
  return out;
}

}  // namespace zeroreg
