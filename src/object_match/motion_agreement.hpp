// Do the matched objects move together? (docs/MATCHING.md "Matches that move together")
//
// Each matched object pair comes with its point support: the point matches between the two
// objects that one rigid motion explains (its inliers). The whole scene moves rigidly between two
// scans, so two right matches move together, even when an object is seen partly and its centroid
// moves (a check of centroid distances cannot tell that case from a wrong match). Two matches agree
// when one rigid motion fitted to both's inliers carries at least half of each's inliers to within
// the threshold: fitted to two objects, the motion has a lever arm of metres, where a cup's own
// motion has centimetres. When a strict majority of the matches agree pairwise, the others are
// dropped; otherwise nothing is decided and every match stays.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// A matched object pair's point-support inliers: the correspondences its own rigid motion
// explains (source and target points, parallel).
struct MatchMotion {
  std::vector<Eigen::Vector3d> source, target;
};

// True when one rigid motion fitted to the inliers of both carries at least half of a's and half
// of b's within threshold_m; false when either has no inliers (no motion of its own).
bool MotionsAgree(const MatchMotion& a, const MatchMotion& b, double threshold_m);

// Indices (ascending) of the matches to keep: the largest set that agree pairwise, when it holds
// more than half of the matches; all of them otherwise (fewer than two matches included).
std::vector<int> MatchesThatMoveTogether(const std::vector<MatchMotion>& motions,
                                         double threshold_m);

// The consensus of MatchesThatMoveTogether: the indices (ascending) of the largest set of at
// least two matches that agree pairwise, when it holds more than half of them; empty otherwise.
std::vector<int> MatchesInConsensus(const std::vector<MatchMotion>& motions, double threshold_m);

// A candidate object pair for CompleteByMotion: its objects and its point-support inliers.
struct MotionCandidate {
  int source = 0, target = 0;
  MatchMotion motion;
};

// Candidates (indices into `candidates`) that join a consensus of matches moving together: a
// candidate whose objects no consensus match and no earlier joined candidate uses, with at least
// min_inliers point-support inliers, joins when its motion agrees (MotionsAgree) with every
// consensus match's and every earlier joined candidate's, so the set stays one that agrees
// pairwise. Candidates are tried by descending inlier count, then by (source, target). Nothing
// joins an empty consensus.
std::vector<int> CompleteByMotion(const std::vector<MotionCandidate>& consensus,
                                  const std::vector<MotionCandidate>& candidates, int min_inliers,
                                  double threshold_m);

// How many of the point pairs (source[i], target[i]) motion T carries to within threshold_m.
int CountCarried(const Transform& T, const MatchMotion& points, double threshold_m);

}  // namespace zeroreg
