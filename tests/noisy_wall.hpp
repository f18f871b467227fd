// A synthetic view with known depth noise, for the tests of the depth-noise measurement and of
// the noise floors that use it (lifting, segmentation).
#pragma once

#include <random>

#include "zeroreg/types.hpp"

namespace zeroreg::testing {

// A 640x480 view (f = 585 px, Kinect v1) of a slanted wall, 1.5 m deep at the left edge and
// 3 m at the right, with a box standing 0.5 m in front of it (x in 251..399, y > 200: two
// vertical depth edges and a horizontal one), and Gaussian noise sigma(d) = noise_at_1m d^2 added
// to every reading. Colour: black wall, white box.
inline View NoisyWall(double noise_at_1m, unsigned seed) {
  View v;
  v.intrinsics = {585, 585, 319.5, 239.5, 640, 480};
  v.color = cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  v.depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(0.0f));
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      // A plane: 1/d is affine in the pixel coordinates.
      double d = 1.0 / (1.0 / 1.5 + (1.0 / 3.0 - 1.0 / 1.5) * x / 639.0);
      if (x > 250 && x < 400 && y > 200) {
        d -= 0.5;
        v.color.at<cv::Vec3b>(y, x) = cv::Vec3b(255, 255, 255);
      }
      v.depth.at<float>(y, x) = static_cast<float>(d + noise_at_1m * d * d * unit(rng));
    }
  }
  return v;
}

}  // namespace zeroreg::testing
