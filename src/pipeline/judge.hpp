// The judge: one way to turn a source's proposal into a judged candidate. Estimate (RANSAC or the
// clique estimator on the correspondences, the last step of paper §3.4 after Eq. 4), the count test
// (RansacConfig), the geometric check (src/verify), ICP kept only when the check prefers it, and
// the caller's motion prior. What decides between judged candidates is the arbiter's (arbiter.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/prepared.hpp"
#include "pipeline/stage_timer.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/register.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// What ICP's refinement of an estimate must keep of the estimate's inliers within the gate of
// Judge::Refine, beyond the method's own test. Three correspondences agree with some motion
// whenever their pairwise distances do; a refined pose that keeps fewer than four of the
// estimate's rests on nothing but the check.
struct KeptEvidence {
  // The kept fraction (refine.min_kept_inlier_fraction) applies even where the check refused the
  // estimate: the object centroids, which pin no surface.
  bool fraction_always = false;
  // At least this many are kept, whether or not the check accepted the estimate; 0 = no floor
  // (the method's own estimate). With a floor, the estimate is also not valid when its rejected
  // refinement is a pose the check accepts too, farther than ICP's widest gate: the other
  // sources' refused estimates on repeated structure are a few degrees off and ICP reaches the
  // truth keeping a small part of them, while ICP from a geometry estimate that kept 1 of 261
  // correspondences went 176 deg wrong (scripts/bench-negatives.py).
  int min_kept = 0;
};

// One proposal of a source: correspondences (or, for the motion prior, a pose) and how they are
// to be judged.
struct Proposal {
  Path path;               // RegistrationResult::path of the candidate it becomes
  std::string check_name;  // the check's CandidateSummary name; empty = path
  std::vector<Correspondence> correspondences;
  std::optional<Transform> pose;  // a pose to start from instead of correspondences (the prior)
  PipelineConfig effective;       // estimator, count test and inlier distance for this source
  KeptEvidence keep;              // what ICP's refinement must keep
  // hypotheses.refuse_degenerate: correspondences too weak to fix the motion a degenerate
  // geometry leaves open (every extra source).
  bool refuse_degenerate = false;
  // The correspondences come from no image (geometry, centroids): the images must agree where
  // the depth does (hypotheses.min_brightness_rank_correlation).
  bool images_must_agree = false;
  // View synthesis: the virtual camera the correspondences' target pixels are in.
  std::optional<RenderedCamera> rendered_view;
};

// A judged candidate: the finished result and, where a source's own test overrode a passing
// check, which one (empty when none did).
struct Judged {
  RegistrationResult result;
  std::string refusal;
  bool valid_before_icp = false;  // valid after the check and the prior, before ICP
};

class Judge {
 public:
  Judge(const Prepared& source, const Prepared& target, const PipelineConfig& config,
        const std::optional<MotionPrior>& prior)
      : source_(source), target_(target), config_(config), prior_(prior) {}

  // Estimate from `correspondences` under `effective` and the count test (r's path is kept).
  void Estimate(std::vector<Correspondence> correspondences, const PipelineConfig& effective,
                RegistrationResult* r) const;
  // The geometric check of r's transform, recorded as candidate `name` and folded into the
  // verdict (with verification on, `valid` needs both the count test and the check).
  void Check(const PipelineConfig& effective, const std::string& name, RegistrationResult* r) const;
  // Coarse-to-fine point-to-plane ICP, kept only when the check prefers it and it keeps the
  // estimate's evidence (`rule`).
  void Refine(const PipelineConfig& effective, RegistrationResult* r, KeptEvidence rule = {}) const;
  // A valid result beyond the caller's motion prior is made invalid.
  void ApplyPrior(RegistrationResult* r) const;
  // The whole judgement of a proposal: estimate (or the pose), check, ICP when the count test
  // passed, prior, and the source's own refusals. With a timer, the stages are marked
  // ("estimate", "verify", "refine").
  Judged Full(Proposal proposal, StageTimer* timer = nullptr) const;

  const PipelineConfig& config() const { return config_; }
  const std::optional<MotionPrior>& prior() const { return prior_; }

 private:
  const Prepared& source_;
  const Prepared& target_;
  const PipelineConfig& config_;
  const std::optional<MotionPrior>& prior_;
};

// The judge's rules on the fields of candidates, without scans (Judge's methods measure, these
// decide; tests/pipeline/judge_rules_test.cpp runs them on stand-in candidates).

// The check's verdict `v` folded into a candidate the count test judged (Judge::Check after the
// rendering): recorded as candidate `name`; with count evidence, valid = the check passed and the
// refusal is the check's; without, the count test's reason stands.
void FoldCheck(const VerificationResult& v, const VerifyConfig& config, const std::string& name,
               RegistrationResult* r);

// What becomes of ICP's refinement of `estimate` (Judge::Refine after ICP and the check of its
// pose): `kept` of the estimate's inliers stay within ICP's coarse gate under `refined`'s pose.
struct Refinement {
  enum Verdict { kKept, kLeftItsEvidence, kScoresLower } kept = kKept;
  double gate_m = 0;       // the gate `kept` was counted within
  double kept_needed = 0;  // how many had to stay
  // With kLeftItsEvidence: an extra source's accepted estimate whose refinement is another pose
  // the check accepts, farther than ICP's widest gate (apart_m): the estimate is not valid.
  bool another_pose_passes = false;
  double apart_m = 0;
};
Refinement JudgeRefinement(const RegistrationResult& estimate, const RegistrationResult& refined,
                           int kept, const PipelineConfig& config, KeptEvidence rule);

// A source's own refusals of a valid candidate (Proposal::refuse_degenerate, images_must_agree):
// degenerate geometry, or images whose brightness disagrees where the depth agrees.
void RefuseForTheSource(bool refuse_degenerate, bool images_must_agree, bool from_a_pose,
                        const PipelineConfig& config, Judged* judged);

// How far T is from the prior (rotation angle, deg; translation, m), and whether that is beyond
// its tolerance.
struct PriorDistance {
  double turned_deg = 0, moved_m = 0;
  bool beyond = false;
};
PriorDistance DistanceFromPrior(const MotionPrior& prior, const Transform& T);

// *result becomes `winner`, keeping what belongs to the scans and the method's object level
// (the objects, their matches, the keypoint counts), which the winner's own run did not fill in.
void Adopt(RegistrationResult winner, RegistrationResult* result);

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

}  // namespace zeroreg
