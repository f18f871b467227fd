#include "object_match/surface_overlap.hpp"

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

bool SurfacesCoincide(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target, const Transform& T_target_source,
                      double radius_m, double min_share) {
  if (source.empty() || target.empty()) return false;
  std::vector<Eigen::Vector3d> moved_source;
  moved_source.reserve(source.size());
  for (const Eigen::Vector3d& p : source)
    moved_source.push_back((T_target_source * p.homogeneous()).head<3>());
  const PointKdTree source_tree(moved_source), target_tree(target);
  return ShareNear(moved_source, target_tree, radius_m) >= min_share ||
         ShareNear(target, source_tree, radius_m) >= min_share;
}

}  // namespace zeroreg
