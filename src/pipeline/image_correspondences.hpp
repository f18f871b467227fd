// Whole-image correspondences: features over the full images of the source's and the target's
// views, matched view i with view i (the paper pairs views by index) or every view with every
// view, lifted to 3D with depth. This is the paper's Table 4 row (a), "w/o Object-Level", and the
// fallback when objects find too little.
#pragma once

#include "estimate/lift.hpp"
#include "features/feature_extractor.hpp"
#include "point_match/descriptor_matcher.hpp"

namespace zeroreg {

// Features of one view restricted to keypoints with usable depth, with their 3D points.
struct LiftedFeatures {
  ImageFeatures features;
  std::vector<Eigen::Vector3d> points;  // scan frame, parallel to features.keypoints
};
LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const LiftConfig& lift);

// Usable keypoints over all the views (what the result reports as keypoints_source/target).
int CountKeypoints(const std::vector<LiftedFeatures>& views);

// Matches the views' features over the whole images and appends the 3D correspondences: view i
// with view i, or (all_view_pairs) every source view with every target view, in that order. The
// view pairs are matched on up to `threads` threads (each pair is independent and its matches
// are appended in the same order, so the result does not depend on the thread count).
void MatchWholeImages(const std::vector<LiftedFeatures>& source,
                      const std::vector<LiftedFeatures>& target, const DescriptorMatcher& matcher,
                      bool all_view_pairs, int threads, std::vector<Correspondence>* out);

}  // namespace zeroreg
