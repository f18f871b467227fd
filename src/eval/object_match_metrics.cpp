#include "eval/object_match_metrics.hpp"

#include <cstddef>

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

namespace {

// Kuhn's augmenting path from `row`: true when `row` gets a column, re-seating earlier rows.
bool Augment(std::size_t row, const std::vector<std::vector<bool>>& edges,
             std::vector<bool>* visited, std::vector<std::ptrdiff_t>* row_of_column) {
  for (std::size_t column = 0; column < visited->size(); ++column) {
    if (!edges[row][column] || (*visited)[column]) continue;
    (*visited)[column] = true;
    std::ptrdiff_t& owner = (*row_of_column)[column];
    if (owner < 0 || Augment(static_cast<std::size_t>(owner), edges, visited, row_of_column)) {
      owner = static_cast<std::ptrdiff_t>(row);
      return true;
    }
  }
  return false;
}

}  // namespace

int MaximumBipartiteMatching(const std::vector<std::vector<bool>>& edges, int columns) {
  std::vector<std::ptrdiff_t> row_of_column(static_cast<std::size_t>(columns), -1);
  int matched = 0;
  for (std::size_t row = 0; row < edges.size(); ++row) {
    std::vector<bool> visited(static_cast<std::size_t>(columns), false);
    if (Augment(row, edges, &visited, &row_of_column)) ++matched;
  }
  return matched;
}

int CountMatchableObjectPairs(const MatchableObjects& objects,
                              const std::function<bool(int source, int target)>& right) {
  const std::size_t rows = objects.source_labels.size();
  const std::size_t columns = objects.target_labels.size();
  std::vector<std::vector<bool>> edges(rows, std::vector<bool>(columns, false));
  for (std::size_t s = 0; s < rows; ++s) {
    for (std::size_t t = 0; t < columns; ++t) {
      edges[s][t] = objects.source_labels[s] == objects.target_labels[t] &&
                    right(static_cast<int>(s), static_cast<int>(t));
    }
  }
  return MaximumBipartiteMatching(edges, static_cast<int>(columns));
}

}  // namespace zeroreg
