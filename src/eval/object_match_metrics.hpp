// Object-level matching quality against ground truth (issue 3): a matched object pair is correct
// when the two centroids agree within a distance under the true transform.
#pragma once

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

}  // namespace zeroreg
