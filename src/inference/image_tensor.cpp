#include "inference/image_tensor.hpp"

namespace zeroreg {

std::vector<float> ImagePlanes(const cv::Mat& bgr8, double scale, bool swap_rb) {
  CV_Assert(bgr8.type() == CV_8UC3);
  const size_t plane = bgr8.total();
  std::vector<float> out(3 * plane);
  const float factor = static_cast<float>(scale);
  float* first = out.data();  // channel 0 of the tensor: B, or R when swapped
  float* second = first + plane;
  float* third = second + plane;
  const int first_channel = swap_rb ? 2 : 0, third_channel = swap_rb ? 0 : 2;
  for (int y = 0; y < bgr8.rows; ++y) {
    const cv::Vec3b* row = bgr8.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr8.cols; ++x) {
      *first++ = static_cast<float>(row[x][first_channel]) * factor;
      *second++ = static_cast<float>(row[x][1]) * factor;
      *third++ = static_cast<float>(row[x][third_channel]) * factor;
    }
  }
  return out;
}

}  // namespace zeroreg
