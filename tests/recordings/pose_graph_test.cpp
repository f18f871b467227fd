#include "recordings/pose_graph.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "eval/metrics.hpp"
#include "recordings/synthetic_trajectory.hpp"

namespace zeroreg {
namespace {

using testing::CircleTrajectory;
using testing::DriftedOdometry;
using testing::InverseOf;
using testing::RandomMotion;
using testing::TrajectoryRmse;

// Odometry edges between consecutive nodes, measured on `odometry` (sigma: a few percent of the
// step, as the drift's size), and loop-closure edges measured on `truth`.
std::vector<PoseGraphEdge> OdometryEdges(const std::vector<Transform>& odometry) {
  std::vector<PoseGraphEdge> edges;
  for (std::size_t i = 1; i < odometry.size(); ++i) {
    PoseGraphEdge e;
    e.from = static_cast<int>(i - 1);
    e.to = static_cast<int>(i);
    e.T_from_to = InverseOf(odometry[i - 1]) * odometry[i];
    e.rotation_sigma_rad = 0.01;
    e.translation_sigma_m = 0.01;
    edges.push_back(e);
  }
  return edges;
}

PoseGraphEdge LoopEdge(const std::vector<Transform>& truth, int from, int to) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to =
      InverseOf(truth[static_cast<std::size_t>(from)]) * truth[static_cast<std::size_t>(to)];
  e.rotation_sigma_rad = 0.005;
  e.translation_sigma_m = 0.005;
  e.kind = PoseGraphEdge::Kind::kLoopClosure;
  return e;
}

// Revisits: the second lap of a two-lap walk sees the places of the first again.
std::vector<PoseGraphEdge> RevisitEdges(const std::vector<Transform>& truth, int lap, int every) {
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i + lap < static_cast<int>(truth.size()); i += every) {
    edges.push_back(LoopEdge(truth, i, i + lap));
  }
  return edges;
}

TEST(PoseGraph, ExactEdgesRecoverTheTruthFromADriftedStart) {
  const std::vector<Transform> truth = CircleTrajectory(40, 2.0, 2.0);
  const std::vector<Transform> start = DriftedOdometry(truth, 1, 0.05, 1.0);
  std::vector<PoseGraphEdge> edges = OdometryEdges(truth);
  for (const PoseGraphEdge& e : RevisitEdges(truth, 20, 5)) edges.push_back(e);
  ASSERT_GT(TrajectoryRmse(start, truth), 0.1);

  const PoseGraphResult result = OptimizePoseGraph(start, edges, {0});
  ASSERT_EQ(result.T_world_node.size(), truth.size());
  EXPECT_TRUE(result.converged);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_LT(RotationErrorDeg(result.T_world_node[i], truth[i]), 1e-4) << "node " << i;
    EXPECT_LT(TranslationErrorM(result.T_world_node[i], truth[i]), 1e-6) << "node " << i;
  }
  for (double r : result.edge_residual_sigmas) EXPECT_LT(r, 1e-3);
}

TEST(PoseGraph, LoopClosuresBringDriftedOdometryBack) {
  const std::vector<Transform> truth = CircleTrajectory(60, 2.0, 2.0);
  const std::vector<Transform> odometry = DriftedOdometry(truth, 2, 0.03, 0.5);
  std::vector<PoseGraphEdge> edges = OdometryEdges(odometry);
  for (const PoseGraphEdge& e : RevisitEdges(truth, 30, 3)) edges.push_back(e);
  const double before = TrajectoryRmse(odometry, truth);
  ASSERT_GT(before, 0.05);

  const PoseGraphResult result = OptimizePoseGraph(odometry, edges, {0});
  EXPECT_TRUE(result.converged);
  EXPECT_LT(TrajectoryRmse(result.T_world_node, truth), before / 3);
}

// One wrong loop closure (30 deg and 1 m off) among right ones: with the robust loss it is left
// pulling against the rest (the largest residual by far) and the trajectory is as good as without
// it (within 5 mm); without the robust loss the graph bends toward it.
TEST(PoseGraph, AWrongLoopClosureDoesNotBendTheTrajectory) {
  const std::vector<Transform> truth = CircleTrajectory(60, 2.0, 2.0);
  const std::vector<Transform> odometry = DriftedOdometry(truth, 3, 0.03, 0.5);
  std::vector<PoseGraphEdge> edges = OdometryEdges(odometry);
  for (const PoseGraphEdge& e : RevisitEdges(truth, 30, 6)) edges.push_back(e);
  std::mt19937 rng(4);
  PoseGraphEdge wrong = LoopEdge(truth, 12, 47);
  wrong.T_from_to = wrong.T_from_to * RandomMotion(rng, 30.0, 1.0);
  const std::size_t wrong_index = edges.size();
  edges.push_back(wrong);
  const double before = TrajectoryRmse(odometry, truth);
  std::vector<PoseGraphEdge> right_only = edges;
  right_only.pop_back();
  const double right_only_error =
      TrajectoryRmse(OptimizePoseGraph(odometry, right_only, {0}).T_world_node, truth);
  ASSERT_LT(right_only_error, before);

  const PoseGraphResult robust = OptimizePoseGraph(odometry, edges, {0});
  const double robust_error = TrajectoryRmse(robust.T_world_node, truth);
  EXPECT_LT(robust_error, right_only_error + 0.005);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i == wrong_index) continue;
    EXPECT_LT(robust.edge_residual_sigmas[i], robust.edge_residual_sigmas[wrong_index]) << i;
  }
  EXPECT_GT(robust.edge_residual_sigmas[wrong_index], 10.0);

  PoseGraphConfig plain;
  plain.loop_loss_scale_sigmas = 0;
  const PoseGraphResult bent = OptimizePoseGraph(odometry, edges, {0}, plain);
  EXPECT_GT(TrajectoryRmse(bent.T_world_node, truth), 3 * robust_error);
}

TEST(PoseGraph, FixedNodesStayWhereTheyAre) {
  const std::vector<Transform> truth = CircleTrajectory(20, 1.5);
  const std::vector<Transform> odometry = DriftedOdometry(truth, 5, 0.05, 1.0);
  std::vector<Transform> start = odometry;
  std::mt19937 rng(6);
  start[0] = truth[0] * RandomMotion(rng, 10.0, 0.5);
  const PoseGraphResult result = OptimizePoseGraph(start, OdometryEdges(odometry), {0});
  EXPECT_TRUE(result.T_world_node[0].isApprox(start[0], 1e-12));
}

TEST(PoseGraph, RefusesEdgesToMissingNodesAndAFloatingGraph) {
  const std::vector<Transform> poses = CircleTrajectory(5, 1.0);
  PoseGraphEdge e;
  e.from = 0;
  e.to = 7;
  EXPECT_THROW(OptimizePoseGraph(poses, {e}, {0}), std::invalid_argument);
  e.to = 0;
  EXPECT_THROW(OptimizePoseGraph(poses, {e}, {0}), std::invalid_argument);
  e.to = 1;
  e.translation_sigma_m = 0;
  EXPECT_THROW(OptimizePoseGraph(poses, {e}, {0}), std::invalid_argument);
  e.translation_sigma_m = 0.01;
  EXPECT_THROW(OptimizePoseGraph(poses, {e}, {}), std::invalid_argument);
  EXPECT_THROW(OptimizePoseGraph(poses, {e}, {9}), std::invalid_argument);
}

}  // namespace
}  // namespace zeroreg
