// Lifting pixels to 3D with depth (paper §3.2, "Object and Feature Projection").
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// How the pixels of one view are lifted: the depth model's range and edge rule, the lifting
// settings, and the view's own depth noise.
struct ViewLift {
  DepthModel depth;
  LiftConfig lift;
  // a of the view's noise sigma(d) = a d^2 (metres at 1 m) measured from its depth
  // (src/estimate/depth_noise.hpp); 0 = unknown or lift.edge_noise_sigmas off: no noise floor.
  double view_depth_noise_at_1m_m = 0.0;
};

// The ViewLift of `view`, its noise measured from its depth when lift.edge_noise_sigmas is on.
ViewLift LiftForView(const LiftConfig& lift, const DepthModel& depth, const View& view);
// The same with the view's a already measured (0 = unknown), for callers that use it elsewhere too.
ViewLift LiftForView(const LiftConfig& lift, const DepthModel& depth,
                     double view_depth_noise_at_1m_m);

// Back-projects pixel (x, y) of `view` into the scan frame: X_cam = z K^-1 [x y 1]^T, then
// T_scan_camera. Returns nullopt when the depth there is invalid, outside the depth model's
// range, or on a depth edge (see LiftConfig).
std::optional<Eigen::Vector3d> LiftPixel(const View& view, const Eigen::Vector2f& pixel,
                                         const ViewLift& how);

// Back-projects every `stride`-th pixel (in x and y) whose depth lies in [min_depth_m,
// max_depth_m] into the scan frame. With `camera_depth`, also appends each point's depth reading
// (metres along its camera's axis, what the sensor's noise depends on).
std::vector<Eigen::Vector3d> BackProjectView(const View& view, int stride = 1,
                                             double min_depth_m = 0.0, double max_depth_m = 1e9,
                                             std::vector<double>* camera_depth = nullptr);

// Pixel grids that follow the image size. The stages that sample a view on a pixel grid
// (verification, object lifting, the geometry hypotheses, ICP) take a stride setting where 0, the
// default, means "the smallest stride that leaves at most `columns` grid columns across the
// image". The number of samples per view, which those stages' time and count thresholds
// (verify.min_points, objects.min_points) are about, then stays the same whatever the sensor's
// resolution. With kGridColumns = 160 that is every 4th pixel at 640 and 540 px wide (the sensors
// in ../shared, where the strides were chosen as 4), every 8th at 1280 and every 2nd at 320.
inline constexpr int kGridColumns = 160;
struct PixelGrid {
  int stride = 0;              // > 0: every stride-th pixel, whatever the image size; 0: auto
  int columns = kGridColumns;  // auto: at most this many grid columns across the image
  int StrideFor(int image_width) const;
};

// The geometry of a scan: its point cloud when it has one, else all its views back-projected
// (BackProjectView, each view at grid.StrideFor(its width)). `camera_depth`, when given, receives
// each point's depth reading, or is left empty for a point cloud (fused points have no one
// reading).
std::vector<Eigen::Vector3d> ScanPoints(const Scan& scan, PixelGrid grid = PixelGrid{1},
                                        double min_depth_m = 0.0, double max_depth_m = 1e9,
                                        std::vector<double>* camera_depth = nullptr);

}  // namespace zeroreg
