// Do the matched objects move together? (issue 11; docs/MATCHING.md "Matches that move together")
//
// Each matched object pair with point support (object_match.min_point_support) comes with its own
// rigid motion: the one that explains the most of the point matches between the two objects, and
// those matches (its inliers). The whole scene moves rigidly between two scans, so two right
// matches have one motion, even when an object is seen partly and its centroid moves (the
// rigidity check, rigidity.hpp, compares centroids and cannot tell that case from a wrong match).
// Two matches agree when one's motion carries at least half of the other's inliers to within the
// inlier threshold (either way round: a small object's own motion may be poorly determined, a
// large one's judges it). When a strict majority of the matches agree with each other, the others
// are dropped; otherwise nothing is decided and every match stays.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct MatchMotion {
  Transform T_target_source = Transform::Identity();  // the match's own motion
  std::vector<Eigen::Vector3d> source, target;        // its inlier correspondences
};

// True when a's motion carries at least half of b's inliers within threshold_m, or b's a's;
// false when either has no inliers (no motion of its own).
bool MotionsAgree(const MatchMotion& a, const MatchMotion& b, double threshold_m);

// Indices (ascending) of the matches to keep: the largest set that agree pairwise, when it holds
// more than half of the matches; all of them otherwise (fewer than two matches included).
std::vector<int> MatchesThatMoveTogether(const std::vector<MatchMotion>& motions,
                                         double threshold_m);

}  // namespace zeroreg
