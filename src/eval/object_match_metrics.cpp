#include "eval/object_match_metrics.hpp"

#include <opencv2/imgproc.hpp>

#include "estimate/lift.hpp"
#include "estimate/point_kd_tree.hpp"

namespace zeroreg {
namespace {

// Share of `points` within radius_m of some point of `tree`.
double ShareNear(const std::vector<Eigen::Vector3d>& points, const PointKdTree& tree,
                 double radius_m) {
  if (points.empty() || tree.size() == 0) return 0.0;
  int near = 0;
  double distance_sq = 0.0;
  for (const Eigen::Vector3d& p : points) {
    if (tree.Nearest(p, radius_m * radius_m, &distance_sq) >= 0) ++near;
  }
  return static_cast<double>(near) / static_cast<double>(points.size());
}

}  // namespace

ObjectMatchStats CountCorrectObjectMatches(const RegistrationResult& result,
                                           const Transform& T_target_source_gt,
                                           double threshold_m) {
  ObjectMatchStats stats;
  for (const ObjectMatchSummary& m : result.object_matches) {
    const Eigen::Vector3d moved =
        (T_target_source_gt * result.source_objects[m.source].centroid.homogeneous()).head<3>();
    ++stats.matches;
    if ((moved - result.target_objects[m.target].centroid).norm() < threshold_m) ++stats.correct;
  }
  return stats;
}

std::vector<Eigen::Vector3d> ObjectSurface(const Scan& scan, const ObjectSummary& object) {
  std::vector<Eigen::Vector3d> surface;
  for (const ObjectView& v : object.views) {
    if (v.view < 0 || v.view >= static_cast<int>(scan.views.size()) || v.outline.size() < 3)
      continue;
    const View& view = scan.views[static_cast<size_t>(v.view)];
    if (view.depth.empty()) continue;
    cv::Mat1b mask = cv::Mat1b::zeros(view.depth.size());
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{v.outline}, cv::Scalar(255));
    const int stride = PixelGrid{}.StrideFor(view.depth.cols);
    const Intrinsics& K = view.intrinsics;
    for (int y = 0; y < mask.rows; y += stride) {
      for (int x = 0; x < mask.cols; x += stride) {
        const float z = view.depth.at<float>(y, x);
        if (!mask(y, x) || !(z > 0.0f)) continue;
        const Eigen::Vector3d camera((x - K.cx) * z / K.fx, (y - K.cy) * z / K.fy, z);
        surface.push_back((view.T_scan_camera * camera.homogeneous()).head<3>());
      }
    }
  }
  return surface;
}

bool SameSurface(const std::vector<Eigen::Vector3d>& source_surface,
                 const std::vector<Eigen::Vector3d>& target_surface,
                 const Transform& T_target_source, const SameSurfaceTest& test) {
  if (source_surface.empty() || target_surface.empty()) return false;
  std::vector<Eigen::Vector3d> moved_source;
  moved_source.reserve(source_surface.size());
  for (const Eigen::Vector3d& p : source_surface)
    moved_source.push_back((T_target_source * p.homogeneous()).head<3>());
  const PointKdTree source_tree(moved_source), target_tree(target_surface);
  return ShareNear(moved_source, target_tree, test.radius_m) >= test.min_share ||
         ShareNear(target_surface, source_tree, test.radius_m) >= test.min_share;
}

}  // namespace zeroreg
