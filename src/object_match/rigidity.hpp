// Geometric consistency of the matched objects (issue 11): a rigid motion preserves distances, so
// two right object matches (j, k), (j', k') have centroids about as far apart in the source as in
// the target, | |c^p_j - c^p_j'| - |c^q_k - c^q_k'| | <= tolerance, whatever the transform. Eq. 2
// scores each matched edge by the scene graphs' affinities, which are kNN-normalised and so say
// little about metric distance; a chair matched to the other chair of the room, or an object
// matched to a same-label one the other scan does not see, breaks the distances. The matches that
// agree with each other form a clique of the "distances agree" graph; the largest clique is kept,
// as the maximum-clique estimator does for point correspondences (estimate/max_clique.hpp).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "object_match/graph_match.hpp"

namespace zeroreg {

struct RigidityCheck {
  std::vector<ObjectPair> kept;     // in the input order
  std::vector<ObjectPair> dropped;  // in the input order
};

// The largest set of `pairs` whose centroid distances agree pairwise within tolerance_m; among
// sets of one size the one holding the higher node similarities (ties to the earlier pair). When
// no two pairs agree (or there are fewer than two), nothing confirms or contradicts a pair, and
// all are kept. centroids_* are indexed by ObjectPair::source / target. tolerance_m <= 0 keeps all.
RigidityCheck CheckRigidity(const std::vector<ObjectPair>& pairs,
                            const std::vector<Eigen::Vector3d>& centroids_source,
                            const std::vector<Eigen::Vector3d>& centroids_target,
                            double tolerance_m);

}  // namespace zeroreg
