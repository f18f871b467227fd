// Lifting pixels to 3D with depth (paper §3.2, "Object and Feature Projection").
#pragma once

#include <Eigen/Core>
#include <optional>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// Back-projects pixel (x, y) of `view` into the scan frame: X_cam = z K^-1 [x y 1]^T, then
// T_scan_camera. Returns nullopt when the depth there is invalid, outside
// [min_depth_m, max_depth_m], or on a depth edge (see LiftConfig).
std::optional<Eigen::Vector3d> LiftPixel(const View& view, const Eigen::Vector2f& pixel,
                                         const LiftConfig& config);

}  // namespace zeroreg
