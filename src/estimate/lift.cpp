#include "estimate/lift.hpp"

#include <algorithm>
#include <cmath>

#include "estimate/depth_noise.hpp"

namespace zeroreg {

ViewLift LiftForView(const LiftConfig& lift, const DepthModel& depth, const View& view) {
  return LiftForView(lift, depth,
                     lift.edge_noise_sigmas > 0 ? MeasureDepthNoiseAt1m(view).value_or(0.0) : 0.0);
}

ViewLift LiftForView(const LiftConfig& lift, const DepthModel& depth,
                     double view_depth_noise_at_1m_m) {
  return {depth, lift, lift.edge_noise_sigmas > 0 ? view_depth_noise_at_1m_m : 0.0};
}

std::optional<Eigen::Vector3d> LiftPixel(const View& view, const Eigen::Vector2f& pixel,
                                         const ViewLift& how) {
  const int u = static_cast<int>(std::lround(pixel.x()));
  const int v = static_cast<int>(std::lround(pixel.y()));
  const cv::Mat& depth = view.depth;
  if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) return std::nullopt;
  const float z = depth.at<float>(v, u);
  if (!(z >= how.depth.min_m && z <= how.depth.max_m)) return std::nullopt;
  // Depth edge: a much nearer/farther reading within the radius means the pixel may belong to
  // either surface (and colour/depth misalignment makes that likely). Missing readings do not
  // count: HoloLens depth has a regular pattern of thin holes all over the image (data MANIFEST),
  // and treating every hole as an edge dropped most of its keypoints.
  const int r = how.lift.depth_edge_radius_px;
  // The larger of the relative jump and the noise floor (LiftConfig::edge_noise_sigmas).
  const double noise_floor =
      how.lift.edge_noise_sigmas * std::sqrt(2.0) * how.view_depth_noise_at_1m_m * z * z;
  const float tolerance = static_cast<float>(std::max(how.depth.edge_relative * z, noise_floor));
  for (int y = std::max(0, v - r); y <= std::min(depth.rows - 1, v + r); ++y) {
    const float* row = depth.ptr<float>(y);
    for (int x = std::max(0, u - r); x <= std::min(depth.cols - 1, u + r); ++x) {
      if (row[x] > 0.0f && std::abs(row[x] - z) > tolerance) {
        return std::nullopt;
      }
    }
  }
  const Intrinsics& K = view.intrinsics;
  const Eigen::Vector4d camera_point((pixel.x() - K.cx) * z / K.fx, (pixel.y() - K.cy) * z / K.fy,
                                     z, 1.0);
  return (view.T_scan_camera * camera_point).head<3>();
}

std::vector<Eigen::Vector3d> BackProjectView(const View& view, int stride, double min_depth_m,
                                             double max_depth_m,
                                             std::vector<double>* camera_depth) {
  std::vector<Eigen::Vector3d> points;
  const Intrinsics& K = view.intrinsics;
  const Eigen::Matrix3d R = view.T_scan_camera.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = view.T_scan_camera.topRightCorner<3, 1>();
  for (int y = 0; y < view.depth.rows; y += stride) {
    const float* row = view.depth.ptr<float>(y);
    for (int x = 0; x < view.depth.cols; x += stride) {
      const double z = row[x];
      if (!(z > 0 && z >= min_depth_m && z <= max_depth_m)) continue;
      points.push_back(R * Eigen::Vector3d((x - K.cx) * z / K.fx, (y - K.cy) * z / K.fy, z) + t);
      if (camera_depth != nullptr) camera_depth->push_back(z);
    }
  }
  return points;
}

int PixelGrid::StrideFor(int image_width) const {
  if (stride > 0) return stride;
  return std::max(1, (image_width + columns - 1) / std::max(1, columns));
}

std::vector<Eigen::Vector3d> ScanPoints(const Scan& scan, PixelGrid grid, double min_depth_m,
                                        double max_depth_m, std::vector<double>* camera_depth) {
  if (camera_depth != nullptr) camera_depth->clear();
  if (!scan.points.empty()) return scan.points;
  std::vector<Eigen::Vector3d> points;
  for (const View& view : scan.views) {
    const std::vector<Eigen::Vector3d> p = BackProjectView(view, grid.StrideFor(view.depth.cols),
                                                           min_depth_m, max_depth_m, camera_depth);
    points.insert(points.end(), p.begin(), p.end());
  }
  return points;
}

}  // namespace zeroreg
