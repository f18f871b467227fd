#include "recordings/open3d_multiway.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <string>

#include "estimate/rigid_inverse.hpp"
#include "features/fpfh.hpp"
#include "open3d_module/open3d_module.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// The rotation nearest (Frobenius) to the sum of rotations and the mean translation.
Transform ChordalMean(const std::vector<Transform>& poses) {
  Eigen::Matrix3d rotation_sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d translation_sum = Eigen::Vector3d::Zero();
  for (const Transform& T : poses) {
    rotation_sum += T.topLeftCorner<3, 3>();
    translation_sum += T.topRightCorner<3, 1>();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation_sum,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  Transform mean = Transform::Identity();
  mean.topLeftCorner<3, 3>() = svd.matrixU() * fix * svd.matrixV().transpose();
  mean.topRightCorner<3, 1>() = translation_sum / static_cast<double>(poses.size());
  return mean;
}

struct PairEstimate {
  Transform T_target_source = Transform::Identity();
  double fitness = 0.0;
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
};

class Registrar {
 public:
  Registrar(const std::vector<MultiwayKeyframe>& keyframes, const MultiwayConfig& config)
      : config_(config), api_(open3d_module::Module()) {
    FpfhParams params;
    params.voxel_m = config.voxel_m;
    for (size_t k = 0; k < keyframes.size(); ++k) {
      if (keyframes[k].points.empty()) {
        throw MakeInputError("keyframe " + std::to_string(k), "has no points with depth");
      }
      clouds_.push_back(ComputeFpfh(keyframes[k].points, params));
    }
  }

  // ICP from `init` (the recipe refines every edge with it).
  PairEstimate Refine(int source, int target, const Transform& init) const {
    open3d_module::IcpRequest request;
    request.max_distance_m = 1.5 * config_.voxel_m;
    request.normal_radius_m = 2.0 * config_.voxel_m;
    request.init = init;
    open3d_module::IcpResult icp;
    api_.point_to_plane_icp(clouds_[source].points, clouds_[target].points, request, &icp);
    return {icp.T_target_source, icp.fitness, icp.information};
  }

  // FPFH + RANSAC (the recipe's global registration), then ICP.
  PairEstimate Global(int source, int target, int seed) const {
    open3d_module::FeatureRansacRequest request;
    request.max_distance_m = 1.5 * config_.voxel_m;
    request.max_iterations = config_.ransac_max_iterations;
    request.confidence = config_.ransac_confidence;
    request.seed = seed;
    open3d_module::FeatureRansacResult ransac;
    api_.feature_ransac(clouds_[source], clouds_[target], request, &ransac);
    return Refine(source, target, ransac.T_target_source);
  }

 private:
  const MultiwayConfig& config_;
  const open3d_module::Api& api_;
  std::vector<FpfhCloud> clouds_;
};

}  // namespace

MultiwayResult RegisterMultiway(const std::vector<MultiwayKeyframe>& keyframes,
                                const MultiwayConfig& config,
                                const std::function<void(int, int)>& progress) {
  const int n = static_cast<int>(keyframes.size());
  MultiwayResult result;
  result.T_world_keyframe.assign(n, Transform::Identity());
  result.placed.assign(n, false);
  if (n == 0) return result;
  if (keyframes.front().recording != 0) {
    throw MakeInputError("keyframe 0",
                         "belongs to recording B; recording A's keyframes come first");
  }
  const Registrar registrar(keyframes, config);
  auto pair_seed = [&](int source, int target) { return config.seed + source * n + target; };

  std::vector<open3d_module::PoseGraphEdge> graph_edges;
  auto add_edge = [&](int source, int target, const PairEstimate& e, bool loop) {
    result.edges.push_back({source, target, e.T_target_source, e.fitness, loop, false});
    open3d_module::PoseGraphEdge edge;
    edge.source = source;
    edge.target = target;
    edge.T_target_source = e.T_target_source;
    edge.information = e.information;
    edge.uncertain = loop;
    graph_edges.push_back(edge);
  };
  // Odometry edges, and the chain of initial poses along them (each recording in its own frame).
  std::vector<Transform> chain(n, Transform::Identity());
  for (int k = 1; k < n; ++k) {
    if (keyframes[k].recording != keyframes[k - 1].recording) continue;
    const auto& a = keyframes[k - 1].T_rec_camera;
    const auto& b = keyframes[k].T_rec_camera;
    const PairEstimate e = a && b ? registrar.Refine(k - 1, k, RigidInverse(*b) * *a)
                                  : registrar.Global(k - 1, k, pair_seed(k - 1, k));
    add_edge(k - 1, k, e, /*loop=*/false);
    chain[k] = chain[k - 1] * RigidInverse(e.T_target_source);
  }
  for (int k = 0; k < n; ++k) {
    if (keyframes[k].T_rec_camera) chain[k] = *keyframes[k].T_rec_camera;
  }
  // Loop edges: every pair that is not consecutive in one recording.
  std::vector<std::pair<int, int>> candidates;
  for (int target = 0; target < n; ++target) {
    for (int source = target + 1; source < n; ++source) {
      const bool consecutive =
          source == target + 1 && keyframes[source].recording == keyframes[target].recording;
      if (!consecutive) candidates.emplace_back(source, target);
    }
  }
  result.loop_candidates = static_cast<int>(candidates.size());
  int done = 0;
  // The best edge joining the two recordings places B for the initial guess.
  int bridge = -1;
  double bridge_fitness = 0.0;
  for (const auto& [source, target] : candidates) {
    const PairEstimate e = registrar.Global(source, target, pair_seed(source, target));
    if (e.fitness > config.min_fitness) {
      if (keyframes[source].recording != keyframes[target].recording &&
          e.fitness > bridge_fitness) {
        bridge = static_cast<int>(result.edges.size());
        bridge_fitness = e.fitness;
      }
      add_edge(source, target, e, /*loop=*/true);
    }
    if (progress) progress(++done, result.loop_candidates);
  }

  // Initial poses in A's frame: A's chain as it is; B's chain moved onto A's by the bridge.
  std::vector<Transform> world_from_node(n, Transform::Identity());
  Transform A_from_B = Transform::Identity();
  bool b_placed = false;
  if (bridge >= 0) {
    const MultiwayEdge& e = result.edges[bridge];
    const int a = keyframes[e.target].recording == 0 ? e.target : e.source;
    const int b = a == e.target ? e.source : e.target;
    const Transform T_a_b = a == e.target ? e.T_target_source : RigidInverse(e.T_target_source);
    A_from_B = chain[a] * T_a_b * RigidInverse(chain[b]);
    b_placed = true;
  }
  std::vector<int> nodes;  // keyframe index of each graph node
  std::vector<int> node_of(n, -1);
  for (int k = 0; k < n; ++k) {
    const bool in_a = keyframes[k].recording == 0;
    if (!in_a && !b_placed) continue;
    node_of[k] = static_cast<int>(nodes.size());
    nodes.push_back(k);
    world_from_node[nodes.size() - 1] = in_a ? chain[k] : A_from_B * chain[k];
  }
  world_from_node.resize(nodes.size());
  std::vector<open3d_module::PoseGraphEdge> in_graph;
  std::vector<int> edge_of;  // index into result.edges of each graph edge
  for (size_t i = 0; i < graph_edges.size(); ++i) {
    const int s = node_of[graph_edges[i].source], t = node_of[graph_edges[i].target];
    if (s < 0 || t < 0) continue;
    open3d_module::PoseGraphEdge edge = graph_edges[i];
    edge.source = s;
    edge.target = t;
    in_graph.push_back(edge);
    edge_of.push_back(static_cast<int>(i));
  }
  if (!nodes.empty()) {
    open3d_module::PoseGraphOptions options;
    options.max_correspondence_distance_m = 1.5 * config.voxel_m;
    options.edge_prune_threshold = config.edge_prune_threshold;
    options.preference_loop_closure = config.preference_loop_closure;
    options.reference_node = 0;
    open3d_module::Module().optimize_pose_graph(&world_from_node, &in_graph, options);
  }
  for (size_t i = 0; i < in_graph.size(); ++i) result.edges[edge_of[i]].kept = !in_graph[i].pruned;
  for (size_t node = 0; node < nodes.size(); ++node) {
    result.T_world_keyframe[nodes[node]] = world_from_node[node];
    result.placed[nodes[node]] = true;
  }
  // Recording A's frame is the frame of its first keyframe's pose (its recording frame when it
  // has poses): the graph's reference node 0 kept its initial pose, so nothing to re-anchor.
  std::vector<Transform> b_estimates;
  for (int k = 0; k < n; ++k) {
    if (keyframes[k].recording == 1 && result.placed[k] && keyframes[k].T_rec_camera) {
      b_estimates.push_back(result.T_world_keyframe[k] * RigidInverse(*keyframes[k].T_rec_camera));
    }
  }
  if (!b_estimates.empty()) result.T_A_B = ChordalMean(b_estimates);
  return result;
}

}  // namespace zeroreg
