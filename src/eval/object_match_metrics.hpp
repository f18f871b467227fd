// Object-level matching quality against ground truth.
//
// Two measures of a matched object pair:
// - centroids (the issues' precision): correct when the two centroids agree within a distance
//   under the true transform. An object seen partly in one view and whole in the other, or from
//   the other side, moves its centroid by decimetres; a large one (a kitchen counter) by more
//   than 0.3 m, so a right match of it can count as wrong.
// - surfaces: the two objects are the same physical object when enough of one's visible surface
//   (the object's own 3D points) lies on the other's under the true transform. This does not depend
//   on how much of each was seen, so it tells "a second chair" (no shared surface) from "the same
//   counter, other end".
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct ObjectMatchStats {
  int matches = 0;  // matched object pairs (after the label filter)
  int correct = 0;  // of which the centroids agree within the threshold under the ground truth
};

// Centroids of source objects are moved by T_target_source_gt and compared with the matched target
// objects' centroids; 0.3 m by default (objects seen partially shift their centroid).
ObjectMatchStats CountCorrectObjectMatches(const RegistrationResult& result,
                                           const Transform& T_target_source_gt,
                                           double threshold_m = 0.3);

// Surface test on two objects' surface points (ObjectSummary::points: their masks' depth pixels,
// one per 2 cm voxel): at least `min_share` of either object's points, the source's moved into
// the target frame by T_target_source, lie within radius_m of the other object's points.
// Defaults: 5 cm (the 2 cm voxel spacing plus a structured-light sensor's depth noise at 3 m)
// and a fifth of a surface (two views of one object share at least that much of what each sees;
// two different objects share none unless their masks overlap).
struct SameSurfaceTest {
  double radius_m = 0.05;
  double min_share = 0.2;
};
bool SameSurface(const std::vector<Eigen::Vector3d>& source_surface,
                 const std::vector<Eigen::Vector3d>& target_surface,
                 const Transform& T_target_source, const SameSurfaceTest& test = {});

// The most right matches any matcher could return from the objects perception gave: the
// size of the largest one-to-one set of (source, target) object pairs
// with equal labels (the paper's label rule, LabelCompatibilityMask) that `right(source, target)`
// accepts. Objects no detector found, or found under different labels in the two scans, are not in
// it, so "correct matches / matchable pairs" is the matcher's recall and "matchable pairs" bounds
// what better matching alone can add.
struct MatchableObjects {
  const std::vector<std::string>& source_labels;
  const std::vector<std::string>& target_labels;
};
int CountMatchableObjectPairs(const MatchableObjects& objects,
                              const std::function<bool(int source, int target)>& right);

// The largest one-to-one set of edges of a bipartite graph given as rows x columns booleans
// (augmenting paths; the graphs here have tens of nodes).
int MaximumBipartiteMatching(const std::vector<std::vector<bool>>& edges, int columns);

}  // namespace zeroreg
