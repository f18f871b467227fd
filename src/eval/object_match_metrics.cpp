#include "eval/object_match_metrics.hpp"

#include "object_match/surface_overlap.hpp"

namespace zeroreg {

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
  return SurfacesCoincide(source_surface, target_surface, T_target_source, test.radius_m,
                          test.min_share);
}

}  // namespace zeroreg
