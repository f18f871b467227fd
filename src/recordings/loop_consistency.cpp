#include "recordings/loop_consistency.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "estimate/max_clique.hpp"
#include "estimate/rigid_inverse.hpp"
#include "eval/metrics.hpp"

namespace zeroreg {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;

void CheckNode(int node, const OdometryContext& odometry, std::size_t loop_index) {
  const std::size_t n = odometry.T_world_node.size();
  if (node < 0 || static_cast<std::size_t>(node) >= n || odometry.recording_of_node.size() != n ||
      odometry.path_length_m.size() != n) {
    throw std::invalid_argument("loop closure " + std::to_string(loop_index) + " names node " +
                                std::to_string(node) + "; the odometry has " + std::to_string(n) +
                                " nodes (with as many recordings and path lengths)");
  }
}

// Loop l oriented as loop k: its u in the recording of k's u (inverted when it runs the other way).
LoopClosure OrientedLike(const LoopClosure& k, const LoopClosure& l,
                         const OdometryContext& odometry) {
  const auto recording = [&](int node) {
    return odometry.recording_of_node[static_cast<std::size_t>(node)];
  };
  if (recording(l.u) == recording(k.u) && recording(l.v) == recording(k.v)) return l;
  return {l.v, l.u, RigidInverse(l.T_u_v)};
}

}  // namespace

CycleError LoopCycleError(const LoopClosure& k, const LoopClosure& l_given,
                          const OdometryContext& odometry) {
  const LoopClosure l = OrientedLike(k, l_given, odometry);
  const auto pose = [&](int node) { return odometry.T_world_node[static_cast<std::size_t>(node)]; };
  const auto path = [&](int node) {
    return odometry.path_length_m[static_cast<std::size_t>(node)];
  };
  const Transform T_vk_vl = RigidInverse(pose(k.v)) * pose(l.v);
  const Transform T_uk_ul = RigidInverse(pose(k.u)) * pose(l.u);
  // u_k -> v_k -> v_l -> u_l -> u_k.
  const Transform cycle = k.T_u_v * T_vk_vl * RigidInverse(l.T_u_v) * RigidInverse(T_uk_ul);
  CycleError e;
  e.rotation_deg = RotationErrorDeg(cycle, Transform::Identity());
  e.translation_m = cycle.topRightCorner<3, 1>().norm();
  e.odometry_path_m = std::abs(path(k.v) - path(l.v)) + std::abs(path(k.u) - path(l.u));
  const Transform T_uk_vl = k.T_u_v * T_vk_vl;
  e.lever_m =
      std::max({k.T_u_v.topRightCorner<3, 1>().norm(), T_uk_vl.topRightCorner<3, 1>().norm(),
                T_uk_ul.topRightCorner<3, 1>().norm()});
  return e;
}

bool CycleWithinTolerance(const CycleError& error, const LoopConsistencyConfig& config) {
  const double rotation_allowed_deg =
      config.rotation_tolerance_deg + config.drift_rotation_deg_per_m * error.odometry_path_m;
  const double translation_allowed_m = config.translation_tolerance_m +
                                       config.drift_translation_fraction * error.odometry_path_m +
                                       rotation_allowed_deg / kDegreesPerRadian * error.lever_m;
  return error.rotation_deg <= rotation_allowed_deg && error.translation_m <= translation_allowed_m;
}

ConsistentLoopSet SelectConsistentLoops(const std::vector<LoopClosure>& loops,
                                        const OdometryContext& odometry,
                                        const LoopConsistencyConfig& config) {
  for (std::size_t i = 0; i < loops.size(); ++i) {
    CheckNode(loops[i].u, odometry, i);
    CheckNode(loops[i].v, odometry, i);
  }
  ConsistentLoopSet result;
  if (loops.empty()) return result;
  if (loops.size() == 1) {
    result.accepted = {0};
    return result;
  }
  std::vector<std::vector<int>> adjacency(loops.size());
  for (std::size_t k = 0; k < loops.size(); ++k) {
    for (std::size_t l = k + 1; l < loops.size(); ++l) {
      if (CycleWithinTolerance(LoopCycleError(loops[k], loops[l], odometry), config)) {
        adjacency[k].push_back(static_cast<int>(l));
        adjacency[l].push_back(static_cast<int>(k));
      }
    }
  }
  const CliqueSearchResult best = MaximumClique(adjacency, config.max_search_nodes);
  result.exact = best.exact;
  // Several candidates of which none agrees with another: nothing tells the right one.
  if (best.clique.size() < 2) return result;
  result.accepted = best.clique;

  // The largest clique among the rest: a second placement that several loop closures support.
  std::vector<int> rest;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (!std::binary_search(best.clique.begin(), best.clique.end(), static_cast<int>(i))) {
      rest.push_back(static_cast<int>(i));
    }
  }
  std::vector<int> index_in_rest(loops.size(), -1);
  for (std::size_t i = 0; i < rest.size(); ++i) index_in_rest[rest[i]] = static_cast<int>(i);
  std::vector<std::vector<int>> rest_adjacency(rest.size());
  for (std::size_t i = 0; i < rest.size(); ++i) {
    for (int neighbour : adjacency[rest[i]]) {
      if (index_in_rest[neighbour] >= 0) rest_adjacency[i].push_back(index_in_rest[neighbour]);
    }
  }
  const CliqueSearchResult second = MaximumClique(rest_adjacency, config.max_search_nodes);
  result.exact = result.exact && second.exact;
  for (int i : second.clique) result.rival.push_back(rest[i]);
  std::sort(result.rival.begin(), result.rival.end());
  result.ambiguous = result.rival.size() >= 2 &&
                     static_cast<double>(result.rival.size()) >=
                         config.ambiguity_ratio * static_cast<double>(best.clique.size());
  return result;
}

}  // namespace zeroreg
