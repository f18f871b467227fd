// Internal helpers of src/io: checks shared by every loader that turns a colour + depth pair into
// a View (size agreement, depth validity, intrinsics sanity), so that all layouts fail the same
// way.
#pragma once

#include <string>

#include "zeroreg/types.hpp"

namespace zeroreg::detail {

// "640x480" for messages.
std::string SizeString(const cv::Mat& image);

// Checks that the intrinsics can describe a real pinhole camera: all four values finite, fx and fy
// in [side / 100, side * 1000] (fields of view from 179.4 degrees down to 0.06 degrees) and the
// principal point within the image widened by half its size on every side, where side is the
// longer image side. Without a size (width or height 0) any image from 1 to 65535 pixels wide is
// assumed, so only values no image could have are refused. `where` names the source of the
// intrinsics.
void CheckIntrinsics(const Intrinsics& intrinsics, const std::string& where);

// Plausible median depth of a frame in metres: depth sensors (structured light, time of flight,
// stereo, LiDAR-completed depth) measure from ~0.1 m to ~100 m. A median outside this range means
// a depth scale off by orders of magnitude (depth in millimetres read as metres gives ~2000 m).
constexpr double kMinMedianDepthM = 0.05;
constexpr double kMaxMedianDepthM = 100.0;

// Checks the consequence of a depth scale on a converted depth map (CV_32FC1, metres, 0 invalid):
// every valid depth finite and the median valid depth within [kMinMedianDepthM, kMaxMedianDepthM].
// `where` names the depth image, `scale_source` where the scale came from ("--depth-scale",
// "scan.json: views[0].depth_scale"), `depth_scale` its value (0 when the depth was given in
// metres). Throws InputError.
void CheckDepthRange(const cv::Mat& depth_m, const std::string& where,
                     const std::string& scale_source, double depth_scale);

// LoadView with the sources named: `intrinsics_source` (the intrinsics file or the scan.json key)
// and `scale_source` (the option or key the depth scale came from) start the messages about them.
View LoadCheckedView(const std::string& color_path, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size,
                     const std::string& intrinsics_source, double depth_scale,
                     const std::string& scale_source);

// Number of pixels with depth > 0 in a CV_32FC1 depth map.
int CountValidDepth(const cv::Mat& depth_m);

// Assembles a View from an already decoded colour (CV_8UC3) and depth (CV_32FC1, metres) image.
// Throws InputError naming both files if the sizes differ, and naming the depth file if no pixel
// is valid. Intrinsics get the image size and are checked against it (messages start with
// `intrinsics_source`, or "intrinsics of <name>" when it is empty).
View MakeCheckedView(const std::string& name, const cv::Mat& color, const std::string& color_path,
                     const cv::Mat& depth, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size,
                     const std::string& intrinsics_source = "");

}  // namespace zeroreg::detail
