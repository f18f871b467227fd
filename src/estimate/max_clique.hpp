// Rigid transform from 3D correspondences at low inlier ratios: pairwise length consistency and
// maximum-clique inlier selection.
//
// A rigid motion preserves distances, so two correct correspondences (s_i, t_i), (s_j, t_j) satisfy
// | |s_i - s_j| - |t_i - t_j| | <= 2 * noise bound, whatever the transform. Linking every pair
// that does gives a graph in which the correct correspondences form a clique, while outliers are
// consistent with each other only by chance; the largest clique is taken as the inlier set and the
// transform is fitted to it. The idea is that of TEASER++ (Yang, Shi, Carlone, "TEASER: Fast and
// Certifiable Point Cloud Registration", T-RO 2021, §V: maximum clique over the translation and
// rotation invariant measurements) and of MAC (Zhang et al., "3D Registration with Maximal
// Cliques", CVPR 2023); KISS-Matcher (Lim et al., ICRA 2025) prunes the same graph by its k-core
// before the clique. This file is written from those papers' descriptions, not their code.
//
// Unlike RANSAC, whose chance of drawing an all-inlier sample falls with the cube of the inlier
// ratio (2 % inliers: one sample in 125,000), the clique needs no sample to be lucky: its cost is
// the graph (quadratic in the correspondences, hence the cap below) and the search, which is exact
// up to a node budget and deterministic (no random numbers at all; the seed is unused).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "estimate/rigid_ransac.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

// Largest clique of an undirected graph given as adjacency lists (no self loops, symmetric).
// Exact when the search finishes within max_search_nodes branch-and-bound nodes; otherwise the
// largest clique found so far (`exact` false). Deterministic: ties go to the lower vertex index.
struct CliqueSearchResult {
  std::vector<int> clique;  // vertex indices, ascending
  bool exact = true;
  long long search_nodes = 0;
};
CliqueSearchResult MaximumClique(const std::vector<std::vector<int>>& adjacency,
                                 long long max_search_nodes);

// The estimator: keeps at most config.clique_max_correspondences correspondences (the highest
// `scores`, ties to the lower index; all when `scores` is empty and n is within the cap, else the
// first ones), links pairs whose lengths agree within 2 * noise bound (noise bound =
// config.clique_noise_bound_m, or config.inlier_threshold_m when that is 0), fits the rigid
// transform to the maximum clique (Kabsch), then takes the inliers of all correspondences at
// config.inlier_threshold_m and refits until the set is stable, as RANSAC's final step does.
// RansacResult::iterations holds the clique search's branch-and-bound nodes.
RansacResult EstimateRigidClique(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const std::vector<float>& scores, const RansacConfig& config);

// The estimator config.estimator names: "ransac" (EstimateRigidRansac with `seed`) or "clique".
// Throws InputError naming ransac.estimator for any other name.
RansacResult EstimateRigid(const std::vector<Eigen::Vector3d>& source,
                           const std::vector<Eigen::Vector3d>& target,
                           const std::vector<float>& scores, const RansacConfig& config,
                           std::uint64_t seed);
void CheckEstimatorName(const RansacConfig& config);

}  // namespace zeroreg
