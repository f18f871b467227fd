// Internal helpers of src/io: checks shared by every loader that turns a colour + depth pair into
// a View (size agreement, depth validity, intrinsics sanity), so that all layouts fail the same
// way.
#pragma once

#include <string>

#include "zeroreg/types.hpp"

namespace zeroreg::detail {

// "640x480" for messages.
std::string SizeString(const cv::Mat& image);

// Checks fx, fy > 0 and all four values finite. `where` names the source of the intrinsics.
void CheckIntrinsics(const Intrinsics& intrinsics, const std::string& where);

// Number of pixels with depth > 0 in a CV_32FC1 depth map.
int CountValidDepth(const cv::Mat& depth_m);

// Assembles a View from an already decoded colour (CV_8UC3) and depth (CV_32FC1, metres) image.
// Throws InputError naming both files if the sizes differ, and naming the depth file if no pixel
// is valid. Intrinsics get the image size.
View MakeCheckedView(const std::string& name, const cv::Mat& color, const std::string& color_path,
                     const cv::Mat& depth, const std::string& depth_path,
                     const Intrinsics& intrinsics_without_size);

}  // namespace zeroreg::detail
