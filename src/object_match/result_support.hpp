// Does the returned transform support an object match? (object_match.agree_with_result;
// docs/MATCHING.md "Matches the result supports")
//
// Once the pipeline has a transform the scans agree with, two observations of one object either
// have point matches that the transform brings together or surfaces it puts in the same place
// (a right object whose own point matches are wrong, e.g. a cup seen from two sides, still has
// the latter). Two different objects have neither.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "object_match/motion_agreement.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// True when T carries at least 4 of the match's point matches (all of them when it has fewer;
// so a match without point matches is not judged) to within 2 * threshold_m, or when under T a
// fifth of either object's surface points lie within threshold_m of the other's
// (SurfacesCoincide). 4: three point matches fit any motion, the fourth is the first that can
// disagree (as object_match.min_point_support); twice the threshold for the transform's error on
// top of each point's (as the motion agreement); a fifth as the evaluation's surface measure.
bool TransformSupportsMatch(const Transform& T, const MatchMotion& point_matches,
                            const std::vector<Eigen::Vector3d>& source_surface,
                            const std::vector<Eigen::Vector3d>& target_surface, double threshold_m);

}  // namespace zeroreg
