#include "estimate/point_kd_tree.hpp"

#include <algorithm>
#include <numeric>

namespace zeroreg {
namespace {

// Points per leaf: a leaf is scanned linearly, which is cheap next to descending further.
constexpr int kLeafSize = 12;

}  // namespace

PointKdTree::PointKdTree(const std::vector<Eigen::Vector3d>& points) {
  original_index_.resize(points.size());
  std::iota(original_index_.begin(), original_index_.end(), 0);
  points_ = points;
  if (points_.empty()) return;
  nodes_.reserve(2 * points_.size() / kLeafSize + 2);
  Build(0, static_cast<int>(points_.size()));
  // Reorder the points to the leaves' order once the index permutation is final.
  std::vector<Eigen::Vector3d> ordered(points_.size());
  for (size_t i = 0; i < ordered.size(); ++i) ordered[i] = points[original_index_[i]];
  points_ = std::move(ordered);
}

// Splits [begin, end) of original_index_ at the median of the bounding box's longest axis (a
// balanced tree whatever the point distribution). Returns the node's index.
int PointKdTree::Build(int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  Eigen::Vector3d lo = points_[original_index_[begin]], hi = lo;
  for (int i = begin + 1; i < end; ++i) {
    lo = lo.cwiseMin(points_[original_index_[i]]);
    hi = hi.cwiseMax(points_[original_index_[i]]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(original_index_.begin() + begin, original_index_.begin() + middle,
                   original_index_.begin() + end, [&](int a, int b) {
                     const double pa = points_[a][axis], pb = points_[b][axis];
                     return pa < pb || (pa == pb && a < b);  // a strict total order: deterministic
                   });
  const double split = points_[original_index_[middle]][axis];
  const int left = Build(begin, middle);
  const int right = Build(middle, end);
  Node& node = nodes_[id];
  node.axis = axis;
  node.split = split;
  node.left = left;
  node.right = right;
  return id;
}

void PointKdTree::Search(int node_id, const Eigen::Vector3d& query, double* best_sq,
                         int* best) const {
  const Node& node = nodes_[node_id];
  if (node.axis < 0) {
    for (int i = node.begin; i < node.end; ++i) {
      const double dx = query.x() - points_[i].x();
      const double dy = query.y() - points_[i].y();
      const double dz = query.z() - points_[i].z();
      const double d2 = dx * dx + dy * dy + dz * dz;
      // The first point within the gate may sit exactly on it; a later one must be closer.
      if (d2 < *best_sq || (*best < 0 && d2 == *best_sq)) {
        *best_sq = d2;
        *best = i;
      }
    }
    return;
  }
  // Points left of the split have coordinate <= split, those right >= split (the median may be
  // repeated on both sides), so the far side can only hold a point within diff of the plane.
  const double diff = query[node.axis] - node.split;
  const int near_side = diff <= 0 ? node.left : node.right;
  const int far_side = diff <= 0 ? node.right : node.left;
  Search(near_side, query, best_sq, best);
  if (diff * diff <= *best_sq) Search(far_side, query, best_sq, best);
}

int PointKdTree::Nearest(const Eigen::Vector3d& query, double max_distance_sq,
                         double* distance_sq) const {
  if (nodes_.empty()) return -1;
  double best_sq = max_distance_sq;
  int best = -1;
  Search(0, query, &best_sq, &best);
  if (best < 0) return -1;
  *distance_sq = best_sq;
  return original_index_[best];
}

size_t PointKdTree::MemoryBytes() const {
  return points_.size() * sizeof(Eigen::Vector3d) + original_index_.size() * sizeof(int) +
         nodes_.size() * sizeof(Node);
}

}  // namespace zeroreg
