// Object masks (paper §3.2 "Object Detection and Segmentation"): the detection boxes prompt a
// segmenter for one mask per object. The paper uses SAMv2, which OpenCV's DNN cannot run; the
// default here is GrabCut seeded by the box and refined with depth, plus the box itself (ablation)
// and a file reader so that masks made elsewhere (e.g. by SAMv2) can be fed in.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

// The image embedding of a view when the segmenter computes one (SAM's encoder output), kept so
// that later stages can reuse it, e.g. an object appearance descriptor averaged over a mask.
// Cell (row i, column j) covers the image pixels [j, j + 1) * pixels_per_cell horizontally and
// [i, i + 1) * pixels_per_cell vertically (image pixel corners; cells beyond the image are
// padding).
struct ImageEmbedding {
  int channels = 0, rows = 0, cols = 0;  // MobileSAM: 256 x 64 x 64
  std::vector<float> data;               // channels x rows x cols, row-major
  double pixels_per_cell = 0.0;          // MobileSAM: 16 / r, r = 1024 / max(width, height)
  bool empty() const { return data.empty(); }
};

// The masks of all detections of one view.
struct ViewMasks {
  // masks[i]: CV_8UC1 of the image size, 255 inside, for detections[i]; all zero when the
  // segmenter found nothing usable (e.g. a SAM mask below segmenter.sam_min_predicted_iou).
  std::vector<cv::Mat> masks;
  // SAM: the decoder's predicted IoU of masks[i] (0-1, before the depth steps); other backends: -1.
  std::vector<float> predicted_iou;
  ImageEmbedding embedding;  // empty unless the backend computes one (sam)
};

// The depth_noise_at_1m_m of a view whose noise is not known: the depth steps get no noise floor.
inline constexpr double kUnknownDepthNoise = 0.0;

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  virtual std::string name() const = 0;
  // Mask of `detection` (index `index` among the image's detections) in the image `bgr` (CV_8UC3)
  // with depth `depth_m` (CV_32FC1 metres, 0 = invalid, same size). Returns CV_8UC1 of the image
  // size, 255 inside. `image_name` identifies the image for the file backend.
  // `depth_noise_at_1m_m`: a of the view's depth noise sigma(d) = a d^2 (metres at 1 m, measured
  // by the pipeline: src/estimate/depth_noise.hpp), for the noise floor of the depth steps
  // (SegmenterConfig::depth_noise_sigmas); kUnknownDepthNoise (0) = unknown, no floor. Required, so
  // that a caller cannot forget it and silently lose the floor.
  // Throws InputError for images of the wrong type or size, and (file backend) for a missing,
  // unreadable or mismatched mask file.
  virtual cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection& detection,
                          int index, const std::string& image_name, double depth_noise_at_1m_m) = 0;
  // The masks of all `detections` of one view (indices = positions in the vector). The default
  // calls Segment for each; SAM overrides it to run its image encoder once per view.
  virtual ViewMasks SegmentView(const cv::Mat& bgr, const cv::Mat& depth_m,
                                const std::vector<Detection>& detections,
                                const std::string& image_name, double depth_noise_at_1m_m);
};

// Throws InputError naming the field for an unknown backend or an out-of-range parameter. "sam"
// reads its models from `assets_dir` (RequireAsset) and always runs on ONNX Runtime (OpenCV DNN
// cannot load them; `inference.threads` applies): an InputError naming segmenter.backend when the
// build has no ONNX Runtime. `seed`: GrabCut's GMM initialisation (k-means++) draws from
// cv::theRNG(), which is reset to it before every box, so a mask does not depend on what ran
// before it (PipelineConfig::seed). `depth`: the depth jumps that are edges (DepthModel).
std::unique_ptr<Segmenter> MakeSegmenter(const SegmenterConfig& config,
                                         const std::string& assets_dir = "",
                                         const InferenceConfig& inference = {},
                                         std::uint64_t seed = 0, const DepthModel& depth = {});

namespace detail {

// The pixels a box covers: those whose centre (u + 0.5, v + 0.5) lies inside it, clipped to an
// image of size `size`. May be empty.
cv::Rect BoxPixelRect(const cv::Rect2f& box, cv::Size size);

// CV_8UC1, 255 where a pixel has valid depth (> 0 and finite) and, in the square window of
// `radius` px around it, the valid readings spread over more than both `relative` * the pixel's
// depth d and `noise_range_at_1m` * d^2 (the spread noise alone can make; 0 = none), or some pixel
// is invalid and lies in a `min_hole_width_px` x `min_hole_width_px` square of invalid pixels (1 =
// any invalid pixel; SegmenterConfig::min_hole_width_px). Outside the image counts as valid.
cv::Mat DepthEdgeMask(const cv::Mat& depth_m, int radius, double relative,
                      double noise_range_at_1m = 0.0, int min_hole_width_px = 1);

// The depth steps every colour mask goes through (GrabCut's and SAM's): pixels of `candidates`
// (box coordinates) whose depth lies in the band around the median valid depth of `reference`,
// that are not on a depth edge (`edges`, box coordinates), then eroded (SegmenterConfig). Returns
// an empty Mat when `reference` has no valid depth. `size_per_metre_depth` = box shorter side
// (px) / focal length (px). `depth_noise_at_1m_m` as in Segmenter::Segment (the band's floor).
cv::Mat DepthLayer(const cv::Mat& depth, const cv::Mat& edges, const cv::Mat& candidates,
                   const cv::Mat& reference, double size_per_metre_depth,
                   const SegmenterConfig& config, double depth_noise_at_1m_m);

// CV_8UC1, 255 at the pixels of `depth_m` without a reading (0, negative or not finite).
cv::Mat MissingDepth(const cv::Mat& depth_m);

// The pixels of `missing` (MissingDepth) that lie in some `width` x `width` square of missing
// pixels: the holes that are more than a gap in the sensor's sampling
// (SegmenterConfig::min_hole_width_px; width 1 = every missing pixel). Outside the image counts
// as not missing.
cv::Mat WideHoles(const cv::Mat& missing, int width);

// Depth edges (DepthEdgeMask with the config's radius and hole width, jumps above
// `edge_relative` of the depth, the noise floor from `depth_noise_at_1m_m`) inside `box`, computed
// on the box padded by the radius and the hole width, so that they equal the whole image's edges
// cropped to the box. Box coordinates.
cv::Mat BoxDepthEdges(const cv::Mat& depth_m, const cv::Rect& box, const SegmenterConfig& config,
                      double edge_relative, double depth_noise_at_1m_m);

// "<masks_dir>/<image stem>_<index>.png", the file backend's mask path.
std::string MaskFilePath(const std::string& masks_dir, const std::string& image_name, int index);

}  // namespace detail
}  // namespace zeroreg
