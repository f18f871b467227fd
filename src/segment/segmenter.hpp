// Object masks (paper §3.2 "Object Detection and Segmentation"): the detection boxes prompt a
// segmenter for one mask per object. The paper uses SAMv2, which OpenCV's DNN cannot run; the
// default here is GrabCut seeded by the box and refined with depth, plus the box itself (ablation)
// and a file reader so that masks made elsewhere (e.g. by SAMv2) can be fed in.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "detect/detector.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  virtual std::string name() const = 0;
  // Mask of `detection` (index `index` among the image's detections) in the image `bgr` (CV_8UC3)
  // with depth `depth_m` (CV_32FC1 metres, 0 = invalid, same size). Returns CV_8UC1 of the image
  // size, 255 inside. `image_name` identifies the image for the file backend.
  // Throws InputError for images of the wrong type or size, and (file backend) for a missing,
  // unreadable or mismatched mask file.
  virtual cv::Mat Segment(const cv::Mat& bgr, const cv::Mat& depth_m, const Detection& detection,
                          int index, const std::string& image_name) = 0;
};

// Throws InputError naming the field for an unknown backend or an out-of-range parameter.
std::unique_ptr<Segmenter> MakeSegmenter(const SegmenterConfig& config);

namespace detail {

// The pixels a box covers: those whose centre (u + 0.5, v + 0.5) lies inside it, clipped to an
// image of size `size`. May be empty.
cv::Rect BoxPixelRect(const cv::Rect2f& box, cv::Size size);

// CV_8UC1, 255 where a pixel has valid depth (> 0 and finite) and some pixel within `radius` px
// (square window) is invalid or differs in depth by more than `relative` * its depth.
cv::Mat DepthEdgeMask(const cv::Mat& depth_m, int radius, double relative);

// "<masks_dir>/<image stem>_<index>.png", the file backend's mask path.
std::string MaskFilePath(const std::string& masks_dir, const std::string& image_name, int index);

}  // namespace detail
}  // namespace zeroreg
