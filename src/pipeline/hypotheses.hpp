// Several hypotheses, one judge (issue 12, item 1). The method's own estimate comes from the
// correspondences inside matched objects (paper §3.4) or, failing that, from whole-image
// correspondences. At wide baselines both can be wrong or missing while another source is right, so
// further candidate transforms are made from
//   (a) the object correspondences again, with the low-inlier estimator,
//   (b) the whole-image correspondences, with the low-inlier estimator,
//   (c) the scans' geometry: FPFH on the depth clouds, mutual nearest neighbours in feature space,
//   (d) object centroids: every same-label object pair of the two scans,
//   (e) when nothing else is valid, (b) with the source's images turned by the quarter turn that
//       matches the target's best (a camera rolled by 90, 180 or 270 deg),
// each estimated, checked by the geometric verification and refined as the method's own estimate
// is, with what the refinement must keep of the estimate's evidence on top
// (hypotheses.refine_keeps_evidence; register.cpp supplies both as JudgeFns). The best verified
// one is returned; all
// are listed in RegistrationResult::candidates and the winner's source is RegistrationResult::path.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "pipeline/image_correspondences.hpp"
#include "pipeline/stage_timer.hpp"
#include "verify/verify.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// *result becomes `winner`, keeping what belongs to the scans and the method's object level
// (the objects, their matches, the keypoint counts), which the winner's own run did not fill in.
void Adopt(RegistrationResult winner, RegistrationResult* result);

// Estimates a transform from `correspondences` under `effective`, applies the geometric check and
// the ICP refinement, and returns the finished result with path = `path`.
using JudgeFn = std::function<RegistrationResult(const std::string& path,
                                                 std::vector<Correspondence> correspondences,
                                                 const PipelineConfig& effective)>;

// What the method's own run leaves for the extra sources.
struct HypothesisInputs {
  std::vector<Correspondence> object_correspondences;  // (a); empty on the image path
  // (b): computes (or returns the cached) whole-image correspondences; null when unavailable.
  std::function<std::vector<Correspondence>()> whole_image;
  // (e): MatchTurnedWholeImages (the source's images turned by the quarter turn that shares the
  // most distinctive matches with the target); null when unavailable.
  std::function<TurnedWholeImage()> whole_image_turned;
  // The whole-image correspondences were already estimated with ransac.estimator (the fallback).
  bool whole_image_tried = false;
  // The source scan's surface samples (the check's, in its frame; owned by its prepared scan),
  // over which two estimates are compared in degenerate geometry or for a rescued estimate
  // (hypotheses.image_rival_degenerate / _rescued); null or empty: none.
  const std::vector<SurfacePoint>* source_surface = nullptr;
  // The object path's estimate was refused by the check and passed only after ICP
  // (hypotheses.image_rival_rescued).
  bool object_rescued_by_icp = false;
};

// Whether the extra sources run for this result (hypotheses.enabled, verification on, and the
// result not valid unless hypotheses.always).
bool WantMoreHypotheses(const PipelineConfig& config, const RegistrationResult& result);

// Runs the enabled sources, judges (a)-(c) with `judge` and the object centroids (d) with
// `judge_object_pairs` (what their refinements must keep: hypotheses.refine_keeps_evidence), and
// replaces *result by the best valid one (a valid result
// beats an invalid one, then the higher verification score wins; ties keep *result); an invalid
// hypothesis never replaces *result. The candidates of every source are appended to
// result->candidates; the winner's reason says which sources it beat and their scores. Each
// source's time is added to `timer` as "hypothesis <name>".
void JudgeMoreHypotheses(const Scan& source, const Scan& target, const PipelineConfig& config,
                         const HypothesisInputs& inputs, const JudgeFn& judge,
                         const JudgeFn& judge_object_pairs, StageTimer& timer,
                         RegistrationResult* result);

// hypotheses.image_rival: when *result is a valid object-path estimate, judges the whole-image
// correspondences (inputs.whole_image) with `effective` (the method's own estimator) and lets that
// estimate replace *result when it is valid, disagrees with it (EstimateDisplacementRms above
// refine.max_distance_coarse_m) and scores higher. Its candidates are appended to
// result->candidates and the reason says what the rival scored. hypotheses.image_rival_degenerate:
// the same check for an object-path estimate the check found degenerate, where the rival
// replaces it when valid, supported by more inlier correspondences and more than
// refine.max_distance_final_m apart over inputs.source_surface. hypotheses.image_rival_rescued: the
// same check for an object-path estimate only ICP made valid (inputs.object_rescued_by_icp), where
// the rival replaces it when valid, scoring higher and more than refine.max_distance_final_m apart
// over inputs.source_surface, unless the check found the geometry degenerate (then only the
// degenerate rule can replace it). hypotheses.image_rival_single: the rescued rule for an
// object-path estimate that rests on one matched object pair. Returns whether it ran (the
// whole-image correspondences were then estimated with the method's estimator). Time: "hypothesis
// image-rival".
bool JudgeImageRival(const PipelineConfig& config, const PipelineConfig& effective,
                     const HypothesisInputs& inputs, const JudgeFn& judge, StageTimer& timer,
                     RegistrationResult* result);

// RMS distance (metres) between where the two transforms put the source points of both results'
// correspondences; 0 when neither has any.
double EstimateDisplacementRms(const RegistrationResult& a, const RegistrationResult& b);

// Two estimates whose correspondence points lie `apart_m` apart (EstimateDisplacementRms)
// disagree beyond ICP's widest gate (refine.max_distance_coarse_m): neither would refine into the
// other, so they are two answers, not one.
bool Disagree(double apart_m, const PipelineConfig& config);

// RMS distance (metres) between where a and b put the points of `surface`; 0 when it is null or
// empty.
double PointDisplacementRms(const std::vector<SurfacePoint>* surface, const Transform& a,
                            const Transform& b);

// (c) alone: FPFH correspondences between the two scans' geometry (exposed for tests).
std::vector<Correspondence> GeometryCorrespondences(const Scan& source, const Scan& target,
                                                    const PipelineConfig& config);

// (d) alone: one centroid correspondence per same-label object pair, plus every matched pair.
std::vector<Correspondence> ObjectPairCorrespondences(const RegistrationResult& result);

}  // namespace zeroreg
