// Geometric consistency of the matched objects: a rigid motion preserves distances, so
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

// A partly seen object's centroid moves with what is seen of it; by about the change of its visible
// extent. So when the objects' extents are given (radius_* = RMS distance of each object's points
// to its centroid, indexed like centroids_*; empty = 0), pairs (a, b) must agree within
//   tolerance_m + |r^p_a - r^q_a| + |r^p_b - r^q_b|,
// which leaves a table seen whole in one scan and half in the other room to agree.
//
// The largest set of `pairs` whose centroid distances agree pairwise within that; among
// sets of one size the one holding the higher node similarities (ties to the earlier pair). When
// no two pairs agree (or there are fewer than two), nothing confirms or contradicts a pair, and
// all are kept. centroids_* are indexed by ObjectPair::source / target. tolerance_m <= 0 keeps all.
RigidityCheck CheckRigidity(const std::vector<ObjectPair>& pairs,
                            const std::vector<Eigen::Vector3d>& centroids_source,
                            const std::vector<Eigen::Vector3d>& centroids_target,
                            double tolerance_m, const std::vector<double>& radius_source = {},
                            const std::vector<double>& radius_target = {});

// RMS distance of `points` to `centroid` (0 for no points).
double RmsRadius(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centroid);

}  // namespace zeroreg
