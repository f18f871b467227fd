// Pose-graph optimisation over the keyframes of one or more recordings: odometry edges between
// consecutive keyframes and loop-closure edges between revisits, solved with Ceres. Loop closures
// carry a robust loss, so that an edge the others contradict stops pulling instead of bending the
// whole trajectory (the role the line process plays in Choi et al., "Robust Reconstruction of
// Indoor Scenes", CVPR 2015, and switchable constraints in Sünderhauf and Protzel, IROS 2012).
// Eigen and Ceres only.
#pragma once

#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// One relative-pose measurement. T_from_to maps points of node `to`'s frame into node `from`'s
// frame; with poses T_world_node it predicts T_world_from^-1 * T_world_to.
struct PoseGraphEdge {
  enum class Kind { kOdometry, kLoopClosure };
  int from = 0;
  int to = 0;
  Transform T_from_to = Transform::Identity();
  // The measurement's standard deviation: radians about each axis, metres along each. The
  // residual is divided by them, so each edge weighs by its accuracy.
  double rotation_sigma_rad = 0.01;
  double translation_sigma_m = 0.01;
  Kind kind = Kind::kOdometry;
};

struct PoseGraphConfig {
  // Loop-closure edges pass through a Cauchy loss of this scale, in units of the edge's sigmas
  // (the whitened residual norm): an edge k sigmas off pulls like one of about scale sigmas once
  // k >> scale. 0: no robust loss (every edge pulls quadratically).
  double loop_loss_scale_sigmas = 3.0;
  int max_iterations = 200;
};

struct PoseGraphResult {
  std::vector<Transform> T_world_node;  // optimised, one per node
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  // Per edge (in the order given): the whitened residual norm after optimisation, in sigmas. A
  // loop closure far beyond loop_loss_scale_sigmas is one the rest of the graph contradicts.
  std::vector<double> edge_residual_sigmas;
};

// Optimises the poses from `initial_T_world_node`. `fixed_nodes` are held where they are (the
// gauge: at least one node must be fixed, or the graph floats); every edge's nodes must exist.
// Deterministic: one thread, the same result for the same inputs. Throws std::invalid_argument
// for edges naming nodes that do not exist, non-positive sigmas, or no fixed node.
PoseGraphResult OptimizePoseGraph(const std::vector<Transform>& initial_T_world_node,
                                  const std::vector<PoseGraphEdge>& edges,
                                  const std::vector<int>& fixed_nodes,
                                  const PoseGraphConfig& config = {});

// The whitened residual of `edge` under the given poses (rotation error in radians over the
// rotation sigma, translation error in metres over the translation sigma; norm of the six).
double EdgeResidualSigmas(const PoseGraphEdge& edge, const Transform& T_world_from,
                          const Transform& T_world_to);

}  // namespace zeroreg
