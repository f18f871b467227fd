#include "eval/object_match_metrics.hpp"

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
