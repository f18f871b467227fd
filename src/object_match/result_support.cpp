#include "object_match/result_support.hpp"

#include <algorithm>

#include "object_match/surface_overlap.hpp"

namespace zeroreg {
namespace {

constexpr int kCarriedPointMatches = 4;
constexpr double kSharedSurface = 0.2;

}  // namespace

bool TransformSupportsMatch(const Transform& T, const MatchMotion& point_matches,
                            const std::vector<Eigen::Vector3d>& source_surface,
                            const std::vector<Eigen::Vector3d>& target_surface,
                            double threshold_m) {
  const int needed = std::min(kCarriedPointMatches, static_cast<int>(point_matches.source.size()));
  return CountCarried(T, point_matches, 2 * threshold_m) >= needed ||
         SurfacesCoincide(source_surface, target_surface, T, threshold_m, kSharedSurface);
}

}  // namespace zeroreg
