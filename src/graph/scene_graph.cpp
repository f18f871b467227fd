#include "graph/scene_graph.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

void RequireFinite(const Eigen::MatrixXd& m, const std::string& name) {
  if (!m.allFinite()) throw MakeInputError(name, "contains NaN or infinite values");
}

// Rows scaled to unit length; zero rows stay zero so that their cosine with anything is 0.
Eigen::MatrixXd NormalizedRows(const Eigen::MatrixXd& s) {
  Eigen::MatrixXd out = s;
  for (Eigen::Index i = 0; i < s.rows(); ++i) {
    const double norm = s.row(i).norm();
    if (norm > 0.0) out.row(i) /= norm;
  }
  return out;
}

}  // namespace

Eigen::MatrixXd BuildAffinityMatrix(const Eigen::MatrixXd& centroids,
                                    const Eigen::MatrixXd& semantics,
                                    const SceneGraphConfig& config) {
  if (config.knn < 1) {
    throw MakeInputError("scene_graph.knn", "is " + std::to_string(config.knn) + ", expected >= 1");
  }
  if (centroids.cols() != 3) {
    throw MakeInputError("centroids", "has " + std::to_string(centroids.cols()) +
                                          " columns, expected 3 (x, y, z in metres)");
  }
  if (centroids.rows() != semantics.rows()) {
    throw MakeInputError("semantics", "has " + std::to_string(semantics.rows()) +
                                          " rows, expected one per centroid (" +
                                          std::to_string(centroids.rows()) + ")");
  }
  RequireFinite(centroids, "centroids");
  RequireFinite(semantics, "semantics");

  const Eigen::Index n = centroids.rows();
  const Eigen::MatrixXd unit = NormalizedRows(semantics);
  // 1 + cos for every pair; zero vectors give cos = 0 through NormalizedRows.
  const Eigen::MatrixXd edge = (unit * unit.transpose()).array() + 1.0;

  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, n);
  const Eigen::Index k = std::min<Eigen::Index>(config.knn, std::max<Eigen::Index>(n - 1, 0));
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::vector<double> dist2(static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      dist2[static_cast<std::size_t>(i)] = (centroids.row(i) - centroids.row(j)).squaredNorm();
    }
    order.resize(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
    order.erase(order.begin() + j);  // a node is not its own neighbour
    // Stable by index on equal distances, so the graph does not depend on sort internals.
    std::partial_sort(order.begin(), order.begin() + k, order.end(),
                      [&](Eigen::Index a, Eigen::Index b) {
                        const double da = dist2[static_cast<std::size_t>(a)];
                        const double db = dist2[static_cast<std::size_t>(b)];
                        return da < db || (da == db && a < b);
                      });
    for (Eigen::Index r = 0; r < k; ++r) {
      const Eigen::Index nb = order[static_cast<std::size_t>(r)];
      w(j, nb) = edge(j, nb);  // Eq. 1
    }
  }
  if (config.symmetric) w = w.cwiseMax(w.transpose()).eval();
  return w;
}

Eigen::MatrixXd NodeSimilarity(const Eigen::MatrixXd& semantics_source,
                               const Eigen::MatrixXd& semantics_target) {
  if (semantics_source.rows() > 0 && semantics_target.rows() > 0 &&
      semantics_source.cols() != semantics_target.cols()) {
    throw MakeInputError("semantics_target",
                         "has dimension " + std::to_string(semantics_target.cols()) +
                             ", expected the source's " + std::to_string(semantics_source.cols()));
  }
  RequireFinite(semantics_source, "semantics_source");
  RequireFinite(semantics_target, "semantics_target");
  if (semantics_source.rows() == 0 || semantics_target.rows() == 0) {
    return Eigen::MatrixXd::Zero(semantics_source.rows(), semantics_target.rows());
  }
  return (NormalizedRows(semantics_source) * NormalizedRows(semantics_target).transpose()).array() +
         1.0;
}

Eigen::MatrixXd NodeSimilarity(const Eigen::MatrixXd& semantics_source,
                               const Eigen::MatrixXd& semantics_target,
                               const Eigen::MatrixXd& appearance_cosine,
                               const Eigen::MatrixXd& comparable, double appearance_weight) {
  Eigen::MatrixXd C = NodeSimilarity(semantics_source, semantics_target);
  if (!(appearance_weight >= 0.0) || !std::isfinite(appearance_weight)) {
    throw MakeInputError(
        "object_match.appearance_weight",
        "is " + std::to_string(appearance_weight) + ", expected a finite value >= 0");
  }
  for (const auto* m : {&appearance_cosine, &comparable}) {
    if (m->rows() != C.rows() || m->cols() != C.cols()) {
      throw MakeInputError(m == &comparable ? "comparable" : "appearance_cosine",
                           "is " + std::to_string(m->rows()) + " x " + std::to_string(m->cols()) +
                               ", expected " + std::to_string(C.rows()) + " x " +
                               std::to_string(C.cols()) + " (source x target objects)");
    }
  }
  RequireFinite(appearance_cosine, "appearance_cosine");
  RequireFinite(comparable, "comparable");
  if (appearance_weight == 0.0) return C;
  C.array() -= appearance_weight * comparable.array() * (1.0 - appearance_cosine.array());
  return C;
}

}  // namespace zeroreg
