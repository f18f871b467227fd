// PointKdTree against brute force: the same nearest point within the gate and the same
// squared distance bit for bit, on clouds shaped like ICP's (a surface sampled on a grid, random
// points, repeated points) and at the edges (empty tree, gate exactly on a point).
#include "estimate/point_kd_tree.hpp"

#include <gtest/gtest.h>

#include <random>

namespace zeroreg {
namespace {

// The brute-force answer with the tree's rule: the first point reaching the smallest distance.
int BruteForce(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& q, double max_sq,
               double* best_sq) {
  int best = -1;
  double best_d2 = max_sq;
  for (size_t i = 0; i < points.size(); ++i) {
    const double dx = q.x() - points[i].x(), dy = q.y() - points[i].y(), dz = q.z() - points[i].z();
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < best_d2 || (best < 0 && d2 == best_d2)) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  *best_sq = best_d2;
  return best;
}

void ExpectSameAsBruteForce(const std::vector<Eigen::Vector3d>& points,
                            const std::vector<Eigen::Vector3d>& queries, double max_distance) {
  const PointKdTree tree(points);
  ASSERT_EQ(tree.size(), points.size());
  int found = 0;
  for (size_t k = 0; k < queries.size(); ++k) {
    double expected_sq = 0.0, got_sq = -1.0;
    const int expected = BruteForce(points, queries[k], max_distance * max_distance, &expected_sq);
    const int got = tree.Nearest(queries[k], max_distance * max_distance, &got_sq);
    ASSERT_EQ(got < 0, expected < 0) << "query " << k;
    if (got < 0) continue;
    ++found;
    // Ties aside (none in these clouds but the repeated points), the same point.
    EXPECT_EQ(got_sq, expected_sq) << "query " << k;
    EXPECT_EQ(points[got], points[expected]) << "query " << k;
  }
  EXPECT_GT(found, 0);
  EXPECT_LT(found, static_cast<int>(queries.size()));  // the gate refused some
}

TEST(PointKdTree, SameAsBruteForceOnASampledSurface) {
  // A wavy floor and a wall sampled every 2 cm, like a thinned depth cloud.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 60; ++j) {
      points.emplace_back(0.02 * i, 0.02 * j, 0.05 * std::sin(0.1 * i + 0.2 * j));
      if (j < 40) points.emplace_back(0.02 * i, 1.2, 0.02 * j);
    }
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-0.1, 2.1), y(-0.1, 1.3), z(-0.2, 0.9);
  std::vector<Eigen::Vector3d> queries;
  for (int k = 0; k < 3000; ++k) queries.emplace_back(x(rng), y(rng), z(rng));
  for (double gate : {0.02, 0.05, 0.15}) ExpectSameAsBruteForce(points, queries, gate);
}

TEST(PointKdTree, SameAsBruteForceOnRandomAndRepeatedPoints) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 2000; ++k) points.emplace_back(g(rng), g(rng), 0.1 * g(rng));
  for (int k = 0; k < 300; ++k) points.push_back(points[k]);  // exact duplicates
  std::vector<Eigen::Vector3d> queries;
  for (int k = 0; k < 2000; ++k) queries.emplace_back(g(rng), g(rng), 0.3 * g(rng));
  for (int k = 0; k < 50; ++k) queries.push_back(points[k]);  // on a point: distance 0
  ExpectSameAsBruteForce(points, queries, 0.1);
}

TEST(PointKdTree, EdgeCases) {
  double d2 = -1.0;
  EXPECT_EQ(PointKdTree().Nearest(Eigen::Vector3d::Zero(), 1.0, &d2), -1);
  EXPECT_EQ(PointKdTree(std::vector<Eigen::Vector3d>{}).Nearest(Eigen::Vector3d::Zero(), 1.0, &d2),
            -1);
  const PointKdTree one({Eigen::Vector3d(0.0, 0.0, 0.5)});
  EXPECT_EQ(one.Nearest(Eigen::Vector3d::Zero(), 0.25, &d2), 0);  // exactly on the gate: found
  EXPECT_EQ(d2, 0.25);
  EXPECT_EQ(one.Nearest(Eigen::Vector3d::Zero(), 0.2499, &d2), -1);
  EXPECT_GT(one.MemoryBytes(), 0u);
}

}  // namespace
}  // namespace zeroreg
