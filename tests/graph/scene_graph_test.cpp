#include "graph/scene_graph.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Four nodes on the z = 0 plane; distances: d01 = 1, d02 = 3, d03 = 2, d12 = 2, d13 = sqrt(5),
// d23 = sqrt(13). With k = 2: kNN(0) = {1, 3}, kNN(1) = {0, 2}, kNN(2) = {1, 0}, kNN(3) = {0, 1}.
// Semantics (not normalised): cos01 = 0, cos02 = cos12 = cos23 = 1/sqrt(2), cos03 = 1, cos13 = 0.
struct FourNodes {
  Eigen::MatrixXd centroids{{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {0, 2, 0}};
  Eigen::MatrixXd semantics{{1, 0}, {0, 1}, {1, 1}, {2, 0}};
};

TEST(SceneGraph, DirectedKnnMatchesHandComputedEq1) {
  FourNodes g;
  const double r = 1.0 + 1.0 / std::sqrt(2.0);
  const Eigen::MatrixXd expected{{0, 1, 0, 2}, {1, 0, r, 0}, {r, r, 0, 0}, {2, 1, 0, 0}};
  const Eigen::MatrixXd w = BuildAffinityMatrix(g.centroids, g.semantics, {2, false});
  EXPECT_TRUE(w.isApprox(expected, 1e-12)) << w;
}

TEST(SceneGraph, SymmetrisedWithMaxIsTheUnionOfBothDirections) {
  FourNodes g;
  const double r = 1.0 + 1.0 / std::sqrt(2.0);
  const Eigen::MatrixXd expected{{0, 1, r, 2}, {1, 0, r, 1}, {r, r, 0, 0}, {2, 1, 0, 0}};
  const Eigen::MatrixXd w = BuildAffinityMatrix(g.centroids, g.semantics, {2, true});
  EXPECT_TRUE(w.isApprox(expected, 1e-12)) << w;
  EXPECT_TRUE(w.isApprox(w.transpose()));
}

TEST(SceneGraph, SmallGraphIsCompleteAndZeroVectorsHaveCosineZero) {
  const Eigen::MatrixXd centroids{{0, 0, 0}, {5, 0, 0}, {0, 9, 0}};
  const Eigen::MatrixXd semantics{{1, 0}, {0, 0}, {-1, 0}};  // node 1 has no semantic evidence
  const Eigen::MatrixXd w = BuildAffinityMatrix(centroids, semantics, {3, false});
  const Eigen::MatrixXd expected{{0, 1, 0}, {1, 0, 1}, {0, 1, 0}};
  // cos(s0, s2) = -1 gives weight 0 although the edge exists; everything else is 1 + 0.
  EXPECT_TRUE(w.isApprox(expected, 1e-12)) << w;
  EXPECT_EQ(BuildAffinityMatrix(Eigen::MatrixXd(0, 3), Eigen::MatrixXd(0, 4)).size(), 0);
  EXPECT_EQ(BuildAffinityMatrix(Eigen::MatrixXd::Zero(1, 3), Eigen::MatrixXd::Ones(1, 4)),
            Eigen::MatrixXd::Zero(1, 1));
}

TEST(SceneGraph, EqualDistancesGoToTheLowerIndex) {
  // Node 0 has three neighbours at distance 1; with k = 2 it must pick 1 and 2.
  const Eigen::MatrixXd centroids{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  const Eigen::MatrixXd w = BuildAffinityMatrix(centroids, Eigen::MatrixXd::Ones(4, 2), {2, false});
  EXPECT_DOUBLE_EQ(w(0, 1), 2.0);
  EXPECT_DOUBLE_EQ(w(0, 2), 2.0);
  EXPECT_EQ(w(0, 3), 0.0);
}

TEST(SceneGraph, NodeSimilarityMatchesHandComputedValues) {
  const Eigen::MatrixXd source{{1, 0}, {0, 0}, {3, 3}};
  const Eigen::MatrixXd target{{2, 0}, {-1, 1}};
  const double h = 1.0 / std::sqrt(2.0);
  const Eigen::MatrixXd expected{{2, 1 - h}, {1, 1}, {1 + h, 1}};
  EXPECT_TRUE(NodeSimilarity(source, target).isApprox(expected, 1e-12));
  EXPECT_EQ(NodeSimilarity(Eigen::MatrixXd(0, 2), target).rows(), 0);
}

TEST(SceneGraph, RejectsInconsistentInputs) {
  EXPECT_THROW(BuildAffinityMatrix(Eigen::MatrixXd::Zero(3, 3), Eigen::MatrixXd::Zero(2, 4)),
               InputError);
  EXPECT_THROW(BuildAffinityMatrix(Eigen::MatrixXd::Zero(3, 2), Eigen::MatrixXd::Zero(3, 4)),
               InputError);
  EXPECT_THROW(BuildAffinityMatrix(Eigen::MatrixXd::Zero(3, 3), Eigen::MatrixXd::Zero(3, 4), {0}),
               InputError);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Zero(2, 3);
  nan(1, 1) = std::nan("");
  EXPECT_THROW(BuildAffinityMatrix(nan, Eigen::MatrixXd::Ones(2, 2)), InputError);
  EXPECT_THROW(NodeSimilarity(Eigen::MatrixXd::Ones(2, 3), Eigen::MatrixXd::Ones(2, 4)),
               InputError);
}

}  // namespace
}  // namespace zeroreg
