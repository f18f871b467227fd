#include "recordings/pose_graph.hpp"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <memory>
#include <stdexcept>
#include <string>

namespace zeroreg {
namespace {

// A pose as Ceres optimises it: unit quaternion (Eigen order x, y, z, w) and translation.
struct PoseBlock {
  double q[4];
  double t[3];
};

PoseBlock ToBlock(const Transform& T) {
  const Eigen::Quaterniond q(Eigen::Matrix3d(T.topLeftCorner<3, 3>()));
  const Eigen::Quaterniond u = q.normalized();
  return {{u.x(), u.y(), u.z(), u.w()}, {T(0, 3), T(1, 3), T(2, 3)}};
}

Transform FromBlock(const PoseBlock& b) {
  const Eigen::Quaterniond q(b.q[3], b.q[0], b.q[1], b.q[2]);
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(b.t[0], b.t[1], b.t[2]);
  return T;
}

// Residual of one edge: the predicted relative pose T_from^-1 T_to against the measured one,
// as the error rotation's small-angle vector (twice the vector part of the error quaternion)
// over the rotation sigma and the translation difference (in the `from` frame) over the
// translation sigma.
class EdgeResidual {
 public:
  EdgeResidual(const Transform& T_from_to, double rotation_sigma, double translation_sigma)
      : q_measured_(Eigen::Matrix3d(T_from_to.topLeftCorner<3, 3>())),
        t_measured_(T_from_to.topRightCorner<3, 1>()),
        rotation_weight_(1.0 / rotation_sigma),
        translation_weight_(1.0 / translation_sigma) {
    q_measured_.normalize();
  }

  template <typename T>
  bool operator()(const T* q_from_ptr, const T* t_from_ptr, const T* q_to_ptr, const T* t_to_ptr,
                  T* residual_ptr) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_from(q_from_ptr);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_from(t_from_ptr);
    const Eigen::Map<const Eigen::Quaternion<T>> q_to(q_to_ptr);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_to(t_to_ptr);
    const Eigen::Quaternion<T> q_from_inverse = q_from.conjugate();
    const Eigen::Quaternion<T> q_predicted = q_from_inverse * q_to;
    const Eigen::Matrix<T, 3, 1> t_predicted = q_from_inverse * (t_to - t_from);
    const Eigen::Quaternion<T> q_error = q_measured_.template cast<T>().conjugate() * q_predicted;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> residual(residual_ptr);
    // The error quaternion and its negative are the same rotation: take the one with w >= 0 so
    // that a small error gives a small residual.
    const T sign = q_error.w() < T(0) ? T(-2) : T(2);
    residual.template head<3>() = sign * q_error.vec() * T(rotation_weight_);
    residual.template tail<3>() =
        (t_predicted - t_measured_.template cast<T>()) * T(translation_weight_);
    return true;
  }

 private:
  Eigen::Quaterniond q_measured_;
  Eigen::Vector3d t_measured_;
  double rotation_weight_;
  double translation_weight_;
};

void CheckEdges(const std::vector<PoseGraphEdge>& edges, std::size_t num_nodes) {
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const PoseGraphEdge& e = edges[i];
    const auto exists = [&](int node) {
      return node >= 0 && static_cast<std::size_t>(node) < num_nodes;
    };
    if (!exists(e.from) || !exists(e.to) || e.from == e.to) {
      throw std::invalid_argument("pose graph edge " + std::to_string(i) + " joins nodes " +
                                  std::to_string(e.from) + " and " + std::to_string(e.to) +
                                  "; expected two different nodes of 0.." +
                                  std::to_string(num_nodes - 1));
    }
    if (!(e.rotation_sigma_rad > 0) || !(e.translation_sigma_m > 0)) {
      throw std::invalid_argument("pose graph edge " + std::to_string(i) +
                                  " has a sigma that is not a positive number");
    }
  }
}

}  // namespace

double EdgeResidualSigmas(const PoseGraphEdge& edge, const Transform& T_world_from,
                          const Transform& T_world_to) {
  const PoseBlock from = ToBlock(T_world_from);
  const PoseBlock to = ToBlock(T_world_to);
  const EdgeResidual residual(edge.T_from_to, edge.rotation_sigma_rad, edge.translation_sigma_m);
  double r[6];
  residual(from.q, from.t, to.q, to.t, r);
  return Eigen::Map<const Eigen::Matrix<double, 6, 1>>(r).norm();
}

PoseGraphResult OptimizePoseGraph(const std::vector<Transform>& initial_T_world_node,
                                  const std::vector<PoseGraphEdge>& edges,
                                  const std::vector<int>& fixed_nodes,
                                  const PoseGraphConfig& config) {
  const std::size_t n = initial_T_world_node.size();
  CheckEdges(edges, n);
  if (fixed_nodes.empty()) {
    throw std::invalid_argument(
        "pose graph: no fixed node; expected at least one (the graph's frame)");
  }
  for (int node : fixed_nodes) {
    if (node < 0 || static_cast<std::size_t>(node) >= n) {
      throw std::invalid_argument("pose graph: fixed node " + std::to_string(node) +
                                  " does not exist");
    }
  }
  std::vector<PoseBlock> blocks;
  blocks.reserve(n);
  for (const Transform& T : initial_T_world_node) blocks.push_back(ToBlock(T));

  ceres::Problem::Options problem_options;
  // The manifold is shared by every quaternion block; the problem must not delete it per block.
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;
  for (const PoseGraphEdge& e : edges) {
    auto* cost = new ceres::AutoDiffCostFunction<EdgeResidual, 6, 4, 3, 4, 3>(
        new EdgeResidual(e.T_from_to, e.rotation_sigma_rad, e.translation_sigma_m));
    ceres::LossFunction* loss = nullptr;
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure && config.loop_loss_scale_sigmas > 0) {
      // Ceres's Cauchy loss takes the scale a of rho(s) = a^2 log(1 + s / a^2), s the squared
      // residual norm: a is in the residual's units, here sigmas.
      loss = new ceres::CauchyLoss(config.loop_loss_scale_sigmas);
    }
    PoseBlock& from = blocks[static_cast<std::size_t>(e.from)];
    PoseBlock& to = blocks[static_cast<std::size_t>(e.to)];
    problem.AddResidualBlock(cost, loss, from.q, from.t, to.q, to.t);
  }
  for (PoseBlock& b : blocks) {
    if (problem.HasParameterBlock(b.q)) problem.SetManifold(b.q, &quaternion_manifold);
  }
  for (int node : fixed_nodes) {
    PoseBlock& b = blocks[static_cast<std::size_t>(node)];
    if (problem.HasParameterBlock(b.q)) problem.SetParameterBlockConstant(b.q);
    if (problem.HasParameterBlock(b.t)) problem.SetParameterBlockConstant(b.t);
  }

  PoseGraphResult result;
  if (problem.NumResidualBlocks() > 0) {
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = config.max_iterations;
    options.num_threads = 1;  // the same result whatever the machine
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    result.converged = summary.termination_type == ceres::CONVERGENCE;
    result.iterations = static_cast<int>(summary.iterations.size());
    result.initial_cost = summary.initial_cost;
    result.final_cost = summary.final_cost;
  } else {
    result.converged = true;
  }
  result.T_world_node.reserve(n);
  for (const PoseBlock& b : blocks) result.T_world_node.push_back(FromBlock(b));
  result.edge_residual_sigmas.reserve(edges.size());
  for (const PoseGraphEdge& e : edges) {
    result.edge_residual_sigmas.push_back(
        EdgeResidualSigmas(e, result.T_world_node[static_cast<std::size_t>(e.from)],
                           result.T_world_node[static_cast<std::size_t>(e.to)]));
  }
  return result;
}

}  // namespace zeroreg
