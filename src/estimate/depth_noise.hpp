// How noisy a scan's depth is, measured from the depth images themselves (docs/CONFIG.md,
// "Depth noise"). Structured-light and stereo sensors (Kinect v1, PrimeSense, RealSense) measure
// disparity, and their axial noise grows with the square of the depth: sigma(d) = a d^2, with a
// constant noise in inverse depth, a = sigma(1/d). On a locally planar surface 1/d is an affine
// function of the pixel coordinates, so the second difference 1/d(u-k) + 1/d(u+k) - 2/d(u) is
// zero but for noise, whose spread is sqrt(6) a for independent readings. Its median absolute
// deviation over a view (robust to the edges and curved surfaces where the plane assumption
// fails) gives a in metres at 1 m, the unit of verify.depth_noise_at_1m_m and
// refine.depth_noise_at_1m_m.
#pragma once

#include <optional>

#include "zeroreg/types.hpp"

namespace zeroreg {

// a of sigma(d) = a d^2 for one view (metres at 1 m), from second differences k pixels apart in
// x and y, k = the view's pixel grid stride (4 at 640 px wide: Kinect v1 quantises disparity and
// correlates it over a few pixels, so neighbours 1 px apart mostly agree exactly). nullopt when
// fewer than 1000 differences have three valid readings.
std::optional<double> MeasureDepthNoiseAt1m(const View& view);

// The median over the scan's views; nullopt for a scan without depth images (a fused cloud) or
// without a measurable view.
std::optional<double> MeasureDepthNoiseAt1m(const Scan& scan);

// Twice Kinect v1's published 1.5 mm at 1 m (Khoshelham & Elberink 2012): depth noisier than this
// is "noisy" for ICP's sampling (RefineConfig::pixel_stride). Measured with
// scripts/depth-noise.py (docs/CONFIG.md, "Depth noise"): the Kinect v1 / PrimeSense frames of
// 7-Scenes and TUM 1.65-1.76 mm, HoloLens 0.14-1.38 mm.
inline constexpr double kNoisyDepthAt1mM = 0.003;

}  // namespace zeroreg
