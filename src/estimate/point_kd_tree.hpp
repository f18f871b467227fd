// Exact nearest-neighbour search among 3D points, for ICP's closest-point pairs.
//
// Open3D's KDTreeFlann (nanoflann over a dynamic-dimension Eigen map) was 8 % of a registration's
// CPU in `perf`, most of it in ICP's 1-nearest queries. This tree is specialised for what ICP
// asks: one neighbour, in 3D, only within a gate. The gate bounds the search from the start, so
// most branches are never entered. It returns the same neighbour as any exact search (the closest
// point; on an exact tie of squared distances, possibly another of the tied points) and the same
// squared distance bit for bit: dx*dx + dy*dy + dz*dz in that order, in double.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace zeroreg {

class PointKdTree {
 public:
  PointKdTree() = default;
  // Copies `points`; indices returned by Nearest refer to this vector.
  explicit PointKdTree(const std::vector<Eigen::Vector3d>& points);

  // The index of the point closest to `query` whose squared distance is at most max_distance_sq,
  // or -1 when there is none; *distance_sq is set to that squared distance when found.
  int Nearest(const Eigen::Vector3d& query, double max_distance_sq, double* distance_sq) const;

  size_t size() const { return points_.size(); }
  size_t MemoryBytes() const;

 private:
  struct Node {
    // Inner node: children `left` and `right`, split along `axis` at `split`.
    // Leaf (axis = -1): the points points_[begin, end).
    int axis = -1;
    double split = 0.0;
    int left = -1, right = -1;
    int begin = 0, end = 0;
  };
  int Build(int begin, int end);
  void Search(int node, const Eigen::Vector3d& query, double* best_sq, int* best) const;

  std::vector<Eigen::Vector3d> points_;  // reordered so that every leaf is a contiguous range
  std::vector<int> original_index_;      // points_[i] was input point original_index_[i]
  std::vector<Node> nodes_;
};

}  // namespace zeroreg
