#include "object_match/rigidity.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace zeroreg {
namespace {

// Exact search for the clique of `linked` (vertices in descending node similarity) that is largest,
// then has the highest summed node similarity. Include-or-exclude branching with a size bound: a
// pair has a few dozen matched objects at most, where this is instantaneous.
struct CliqueSearch {
  const std::vector<std::vector<bool>>& linked;
  const std::vector<double>& similarity;
  std::vector<int> best, current;
  double best_similarity = -1, current_similarity = 0;

  void Expand(int next) {
    const int n = static_cast<int>(similarity.size());
    if (current.size() > best.size() ||
        (current.size() == best.size() && current_similarity > best_similarity)) {
      best = current;
      best_similarity = current_similarity;
    }
    for (int v = next; v < n; ++v) {
      if (current.size() + static_cast<size_t>(n - v) < best.size()) return;  // cannot win
      bool fits = true;
      for (int u : current) fits = fits && linked[static_cast<size_t>(u)][static_cast<size_t>(v)];
      if (!fits) continue;
      current.push_back(v);
      current_similarity += similarity[static_cast<size_t>(v)];
      Expand(v + 1);
      current.pop_back();
      current_similarity -= similarity[static_cast<size_t>(v)];
    }
  }
};

// |r^p - r^q| of one matched pair; 0 without radii.
double ExtentChange(const ObjectPair& pair, const std::vector<double>& radius_source,
                    const std::vector<double>& radius_target) {
  if (radius_source.empty() || radius_target.empty()) return 0.0;
  return std::abs(radius_source[static_cast<size_t>(pair.source)] -
                  radius_target[static_cast<size_t>(pair.target)]);
}

}  // namespace

double RmsRadius(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centroid) {
  if (points.empty()) return 0.0;
  double sum = 0;
  for (const Eigen::Vector3d& p : points) sum += (p - centroid).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

RigidityCheck CheckRigidity(const std::vector<ObjectPair>& pairs,
                            const std::vector<Eigen::Vector3d>& centroids_source,
                            const std::vector<Eigen::Vector3d>& centroids_target,
                            double tolerance_m, const std::vector<double>& radius_source,
                            const std::vector<double>& radius_target) {
  RigidityCheck out;
  const int n = static_cast<int>(pairs.size());
  if (tolerance_m <= 0 || n < 2) {
    out.kept = pairs;
    return out;
  }
  // Vertices in descending node similarity, so that the clique search's ties (to the lower
  // vertex) go to the pairs that look more alike.
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return pairs[static_cast<size_t>(a)].node_similarity >
           pairs[static_cast<size_t>(b)].node_similarity;
  });
  std::vector<std::vector<bool>> linked(static_cast<size_t>(n),
                                        std::vector<bool>(static_cast<size_t>(n), false));
  std::vector<double> similarity;
  for (int i : order) similarity.push_back(pairs[static_cast<size_t>(i)].node_similarity);
  for (int a = 0; a < n; ++a) {
    const ObjectPair& pa = pairs[static_cast<size_t>(order[static_cast<size_t>(a)])];
    for (int b = a + 1; b < n; ++b) {
      const ObjectPair& pb = pairs[static_cast<size_t>(order[static_cast<size_t>(b)])];
      const double ds = (centroids_source[static_cast<size_t>(pa.source)] -
                         centroids_source[static_cast<size_t>(pb.source)])
                            .norm();
      const double dt = (centroids_target[static_cast<size_t>(pa.target)] -
                         centroids_target[static_cast<size_t>(pb.target)])
                            .norm();
      const double slack = ExtentChange(pa, radius_source, radius_target) +
                           ExtentChange(pb, radius_source, radius_target);
      if (std::abs(ds - dt) <= tolerance_m + slack) {
        linked[static_cast<size_t>(a)][static_cast<size_t>(b)] = true;
        linked[static_cast<size_t>(b)][static_cast<size_t>(a)] = true;
      }
    }
  }
  CliqueSearch search{linked, similarity, {}, {}};
  search.Expand(0);
  const std::vector<int>& clique = search.best;
  if (clique.size() < 2) {
    out.kept = pairs;
    return out;
  }
  std::vector<bool> keep(static_cast<size_t>(n), false);
  for (int v : clique) keep[static_cast<size_t>(order[static_cast<size_t>(v)])] = true;
  for (int i = 0; i < n; ++i) {
    (keep[static_cast<size_t>(i)] ? out.kept : out.dropped)
        .push_back(pairs[static_cast<size_t>(i)]);
  }
  return out;
}

}  // namespace zeroreg
