// Which loop closures to trust together: pairwise consistency and a maximum clique, as PCM does
// (Mangelson, Dominic, Eustice, Vasudevan, "Pairwise Consistent Measurement Set Maximization for
// Robust Multi-robot Map Merging", ICRA 2018). Written from the paper's description.
//
// Two right loop closures k and l, with the odometry between their ends, close a cycle:
//   u_k --(loop k)--> v_k --(odometry)--> v_l --(loop l, inverted)--> u_l --(odometry)--> u_k
// whose composed transform is the identity up to the loops' registration error and the drift the
// odometry gathered along the cycle. A wrong loop closure is off by far more than that against
// every right one, and agrees with another wrong one only when both are wrong the same way (the
// half turns of a symmetric object are: ConsistentLoopSet reports them as ambiguous).
// Eigen only.
#pragma once

#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// A loop closure between node u and node v (keyframes of one recording, or of two), with the
// registered transform T_u_v that maps v's camera frame into u's.
struct LoopClosure {
  int u = 0;
  int v = 0;
  Transform T_u_v = Transform::Identity();
};

// What a cycle may be off by, and how that grows along the odometry.
struct LoopConsistencyConfig {
  // The two loop closures' own registration error, together (degrees, metres).
  double rotation_tolerance_deg = 4.0;
  double translation_tolerance_m = 0.08;
  // Odometry drift per metre travelled along the cycle's odometry legs: translation as a fraction
  // of the distance, rotation in degrees per metre.
  double drift_translation_fraction = 0.02;
  double drift_rotation_deg_per_m = 0.5;
  // A second clique disjoint from the largest, with at least this fraction of its size (and at
  // least two loop closures), makes the set ambiguous: two different placements both explain
  // several loop closures.
  double ambiguity_ratio = 0.5;
  long long max_search_nodes = 2000000;  // MaximumClique's budget
};

// How far the cycle of loop closures k and l is from closing.
struct CycleError {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  double odometry_path_m = 0.0;  // metres travelled along the cycle's two odometry legs
  // Farthest of the cycle's nodes from u_k (metres): a rotation error moves points this far out
  // by its angle times this distance.
  double lever_m = 0.0;
};

// `T_world_node`: every node's pose from odometry (each recording in a frame of its own; loop
// closures between two recordings use each node's own recording's frame). `recording_of_node`:
// which recording each node belongs to (the cycle's odometry legs stay within one recording, so
// two loop closures between recordings are compared through the frames' offset they imply).
// `path_length_m[i]`: metres travelled along node i's recording from its first node to node i
// (cumulative odometry path), which measures how much drift the legs gather.
struct OdometryContext {
  std::vector<Transform> T_world_node;
  std::vector<int> recording_of_node;
  std::vector<double> path_length_m;
};

CycleError LoopCycleError(const LoopClosure& k, const LoopClosure& l,
                          const OdometryContext& odometry);

// Whether a cycle error is within what the two loops' errors and the odometry's drift allow.
bool CycleWithinTolerance(const CycleError& error, const LoopConsistencyConfig& config);

struct ConsistentLoopSet {
  std::vector<int> accepted;  // indices into the loop closures, ascending (the largest clique)
  // The largest clique among the loop closures left out of `accepted` (ascending), and whether
  // it is large enough to make the choice ambiguous (LoopConsistencyConfig::ambiguity_ratio).
  std::vector<int> rival;
  bool ambiguous = false;
  bool exact = true;  // both clique searches finished within their budget
};

// The largest set of mutually consistent loop closures. A loop closure consistent with no other
// one cannot be told right from wrong here and is accepted only when it is the only candidate.
// Deterministic (ties to lower indices). Throws std::invalid_argument when a loop names a node
// the odometry does not have.
ConsistentLoopSet SelectConsistentLoops(const std::vector<LoopClosure>& loops,
                                        const OdometryContext& odometry,
                                        const LoopConsistencyConfig& config = {});

}  // namespace zeroreg
