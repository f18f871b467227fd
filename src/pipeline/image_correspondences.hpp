// Whole-image correspondences: features over the full images of the source's and the target's
// views, matched view i with view i (the paper pairs views by index) or every view with every
// view, lifted to 3D with depth. This is the paper's Table 4 row (a), "w/o Object-Level", and the
// fallback when objects find too little.
#pragma once

#include <array>

#include "estimate/lift.hpp"
#include "features/feature_extractor.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

// Features of one view restricted to keypoints with usable depth, with their 3D points.
struct LiftedFeatures {
  ImageFeatures features;
  std::vector<Eigen::Vector3d> points;  // scan frame, parallel to features.keypoints
};
// With `quarter_turns` (1-3) the features are extracted from the colour image turned clockwise by
// that many quarter turns, and their keypoints mapped back to the view's own pixels, so the 3D
// points are the same as unturned (why: HypothesesConfig::turned_images).
LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const ViewLift& lift, int quarter_turns = 0);

// Usable keypoints over all the views (what the result reports as keypoints_source/target).
int CountKeypoints(const std::vector<LiftedFeatures>& views);

// Which view pairs whole-image matching uses (MethodConfig::whole_image_all_view_pairs and
// whole_image_max_view_pairs document them).
struct WholeImageViewPairs {
  static constexpr int kAsManyAsViews = -1;
  bool all = true;  // every source view with every target view; false: view i with view i
  // > 0: of those, only the `max_pairs` with the highest ViewOverlapScore; kAsManyAsViews: as
  // many as the scan with more views has views; 0: all of them.
  int max_pairs = 0;
};

// MethodConfig::whole_image_all_view_pairs and whole_image_max_view_pairs.
WholeImageViewPairs WholeImageViewPairsOf(const MethodConfig& method);

// How much two views look like the same place, cheaply: mutual nearest neighbours among the
// strongest kOverlapScoreKeypoints keypoints of each view that pass Lowe's ratio test (best
// descriptor distance below 0.8 of the second best, Lowe, IJCV 2004). Views that share no
// surface get few (distinctive matches are rare by chance); a shared surface gives many.
constexpr int kOverlapScoreKeypoints = 1024;
int ViewOverlapScore(const LiftedFeatures& a, const LiftedFeatures& b);

// The (source view, target view) pairs to match, in source-major order: all pairs or view i with
// view i; when more than choice.max_pairs, the best max_pairs by ViewOverlapScore (ties to the
// earlier pair). Scored on up to `threads` threads; the choice does not depend on their number.
std::vector<std::pair<int, int>> ChooseViewPairs(const std::vector<LiftedFeatures>& source,
                                                 const std::vector<LiftedFeatures>& target,
                                                 const WholeImageViewPairs& choice, int threads);

// Matches the views' features over the whole images and appends the 3D correspondences of the
// view pairs ChooseViewPairs picks, in that order. The view pairs are matched on up to `threads`
// threads (each pair is independent and its matches are appended in the same order, so the
// result does not depend on the thread count).
void MatchWholeImages(const std::vector<LiftedFeatures>& source,
                      const std::vector<LiftedFeatures>& target, const DescriptorMatcher& matcher,
                      const WholeImageViewPairs& view_pairs, int threads,
                      std::vector<Correspondence>* out);

// Source (e) of the hypotheses (hypotheses.turned_images; docs/CONFIG.md "Turned cameras (e)").
// A scan's features extracted from its views' colour images turned by 1, 2 and 3 quarter turns
// (index 0-2), per view, keypoints in the views' own pixels: they depend on the scan alone.
using TurnedFeatures = std::array<std::vector<LiftedFeatures>, 3>;
TurnedFeatures ExtractTurnedFeatures(const FeatureExtractor& extractor, const Scan& scan,
                                     const std::vector<ViewLift>& lifts);

// Each turn of the source scored by its summed ViewOverlapScore against the target's views (the
// view pairs `view_pairs` allows, before its max_pairs cut), and only the best-scoring turn
// matched (MatchWholeImages), provided it scores above the unturned features and at least
// `min_score` (hypotheses.turned_min_matches): a rolled camera shows as one turn with more
// distinctive matches than the others.
struct TurnedWholeImage {
  int quarter_turns = 0;  // the turn matched; 0: none scores above the unturned and min_score
  int best_turn = 0;      // the best-scoring turn (0: the unturned images), min_score or not
  std::array<int, 4> overlap_scores{};          // per turn 0-3 (0 = unturned)
  std::vector<Correspondence> correspondences;  // the matched turn's; empty for 0
};
TurnedWholeImage MatchTurnedWholeImages(const TurnedFeatures& source_turned,
                                        const std::vector<LiftedFeatures>& source_features,
                                        const std::vector<LiftedFeatures>& target_features,
                                        const DescriptorMatcher& matcher,
                                        const WholeImageViewPairs& view_pairs, int min_score,
                                        int threads);

}  // namespace zeroreg
