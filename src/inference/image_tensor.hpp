// The input tensor of an image model (XFeat, YOLOX): an 8-bit 3-channel image as three planes
// (C x H x W) of pixel x scale.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace zeroreg {

// Channels in the image's BGR order, or R, G, B with swap_rb. The values are exactly those of
// cv::dnn::blobFromImage(bgr8, scale, size, Scalar(), swap_rb) (it converts to float and scales by
// the float of `scale`), written out without its per-channel copies: 6.5 -> 1.6 ms for a 640x480
// frame (docs/SPEED.md). Tested bit for bit (ImageTensor.PlanesAreBlobFromImage).
std::vector<float> ImagePlanes(const cv::Mat& bgr8, double scale, bool swap_rb);

}  // namespace zeroreg
