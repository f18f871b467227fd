// The judge's rules on stand-in candidates: the count test, the check folded into the verdict, ICP
// kept only when the check prefers it and it keeps its evidence, the motion prior's tolerance and
// a source's own refusals, decided from the fields of candidates without images, so that a tuning
// change of the sources or the check does not mean finding a real pair that still shows the rule.
// (decision_rules_test.cpp does the same for the arbiter's rules.)
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "pipeline/judge.hpp"
#include "rigid_motion.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

// Correspondences whose target points are the source points moved by `T`: `exact` of them on a
// 1 m cube's worth of spread (or within 2 cm of a line), then `outliers` with random targets.
std::vector<Correspondence> Correspondences(const Transform& T, int exact, int outliers,
                                            bool on_a_line = false) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Correspondence> out;
  for (int i = 0; i < exact + outliers; ++i) {
    Correspondence c;
    c.source = on_a_line ? Eigen::Vector3d(u(rng), 0.02 * u(rng), 2.0)
                         : Eigen::Vector3d(u(rng), u(rng), 2.0 + 0.5 * u(rng));
    c.target = i < exact ? Eigen::Vector3d((T * c.source.homogeneous()).head<3>())
                         : Eigen::Vector3d(3 * u(rng), 3 * u(rng), 3 + u(rng));
    c.score = 1.0f;
    out.push_back(c);
  }
  return out;
}

// The judge's scan-free methods (Estimate, ApplyPrior) on empty scans.
struct Stand {
  Prepared source, target;
  PipelineConfig config;
  std::optional<MotionPrior> prior;
  Judge judge() const { return Judge(source, target, config, prior); }
};

RegistrationResult Estimated(const std::vector<Correspondence>& c, const PipelineConfig& config) {
  Stand s;
  s.config = config;
  RegistrationResult r;
  s.judge().Estimate(c, config, &r);
  return r;
}

TEST(JudgeRules, CountTestNeedsThreeCorrespondencesEnoughInliersSpreadAndRatio) {
  const PipelineConfig config;  // min_inliers 10, ratio 0.05, spread 0.05 m
  const Transform T = testing::TurnedAboutZ(20) * testing::ShiftedAlongX(0.3);
  // Enough exact correspondences: the count test passes and the estimate is the motion.
  RegistrationResult r = Estimated(Correspondences(T, 30, 0), config);
  EXPECT_TRUE(r.valid && r.count_test_passed) << r.reason;
  EXPECT_EQ(r.refusal.test, RefusalTest::kNone);
  EXPECT_EQ(r.num_inliers, 30);
  EXPECT_LT((r.T_target_source - T).norm(), 1e-6);
  // Fewer than three: no transform.
  r = Estimated(Correspondences(T, 2, 0), config);
  EXPECT_FALSE(r.valid || r.count_test_passed);
  EXPECT_EQ(r.refusal.test, RefusalTest::kFewCorrespondences);
  EXPECT_EQ(r.refusal.measured, 2.0);
  EXPECT_EQ(r.refusal.threshold, 3.0);
  // Below ransac.min_inliers.
  r = Estimated(Correspondences(T, 9, 0), config);
  EXPECT_EQ(r.refusal.test, RefusalTest::kFewInliers);
  EXPECT_EQ(r.refusal.measured, 9.0);
  EXPECT_EQ(r.refusal.threshold, config.ransac.min_inliers);
  // On a line: the rotation about it is undetermined.
  r = Estimated(Correspondences(T, 30, 0, /*on_a_line=*/true), config);
  EXPECT_EQ(r.refusal.test, RefusalTest::kInliersOnALine) << r.reason;
  EXPECT_LT(r.refusal.measured, config.ransac.min_inlier_spread_m);
  // Enough inliers among too many outliers.
  PipelineConfig strict = config;
  strict.ransac.min_inlier_ratio = 0.5;
  r = Estimated(Correspondences(T, 20, 60), strict);
  EXPECT_EQ(r.refusal.test, RefusalTest::kLowInlierRatio) << r.reason;
  EXPECT_NEAR(r.refusal.measured, 0.25, 0.02);
  EXPECT_EQ(r.refusal.threshold, 0.5);
  EXPECT_FALSE(r.count_test_passed);
}

RegistrationResult Counted(bool count_test_passed) {
  RegistrationResult r;
  r.valid = r.count_test_passed = count_test_passed;
  r.reason = "count";
  if (!count_test_passed) r.refusal = {RefusalTest::kFewInliers, 4, 10};
  return r;
}

VerificationResult Checked(bool passed, double overlap, double violation, double score) {
  VerificationResult v;
  v.ran = true;
  v.passed = passed;
  v.overlap = overlap;
  v.violation = violation;
  v.score = score;
  v.source_samples = v.target_samples = 1000;
  v.reason = "check";
  return v;
}

TEST(JudgeRules, ValidNeedsTheCountTestAndTheCheck) {
  const VerifyConfig config;
  // Count evidence and a passing check: valid, recorded as a passed candidate.
  RegistrationResult r = Counted(true);
  FoldCheck(Checked(true, 0.6, 0.01, 0.5), config, "object ransac", &r);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.refusal.test, RefusalTest::kNone);
  ASSERT_EQ(r.candidates.size(), 1u);
  EXPECT_TRUE(r.candidates[0].passed);
  EXPECT_EQ(r.candidates[0].name, "object ransac");
  EXPECT_EQ(r.candidates[0].score, 0.5);
  // Count evidence and a refused check: not valid, the check's refusal as data.
  r = Counted(true);
  FoldCheck(Checked(false, 0.6, 0.3, 0.1), config, "object ransac", &r);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.refusal.test, RefusalTest::kFreeSpaceViolation);
  EXPECT_EQ(r.refusal.measured, 0.3);
  EXPECT_EQ(r.refusal.threshold, config.max_violation);
  r = Counted(true);
  FoldCheck(Checked(false, 0.05, 0.0, 0.05), config, "object ransac", &r);
  EXPECT_EQ(r.refusal.test, RefusalTest::kLowOverlap);
  EXPECT_EQ(r.refusal.threshold, config.min_overlap);
  r = Counted(true);
  VerificationResult little = Checked(false, 0.0, 0.0, 0.0);
  little.source_samples = 50;
  FoldCheck(little, config, "object ransac", &r);
  EXPECT_EQ(r.refusal.test, RefusalTest::kLittleDepth);
  EXPECT_EQ(r.refusal.measured, 50.0);
  // Without count evidence a passing check makes nothing valid: the count refusal stands, and the
  // candidate is not listed as passed.
  r = Counted(false);
  FoldCheck(Checked(true, 0.9, 0.0, 0.8), config, "object ransac", &r);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.refusal.test, RefusalTest::kFewInliers);
  EXPECT_EQ(r.reason, "count");
  ASSERT_EQ(r.candidates.size(), 1u);
  EXPECT_FALSE(r.candidates[0].passed);
}

// An estimate with `inliers` inlier correspondences at x = 0..inliers-1 (a line of points 1 m
// apart, each mapped onto itself), its check's verdict and score.
RegistrationResult Estimate(bool passed, double score, int inliers) {
  RegistrationResult r;
  r.valid = r.count_test_passed = true;
  r.verification = Checked(passed, 0.5, 0.0, score);
  r.valid = passed;
  r.num_inliers = inliers;
  for (int i = 0; i < inliers; ++i) {
    Correspondence c;
    c.source = c.target = Eigen::Vector3d(i, 0.0, 2.0);
    r.correspondences.push_back(c);
    r.is_inlier.push_back(true);
  }
  return r;
}

RegistrationResult RefinedTo(const RegistrationResult& estimate, const Transform& T, bool passed,
                             double score, bool degenerate = false) {
  RegistrationResult r = estimate;
  r.T_target_source = T;
  r.verification = Checked(passed, 0.5, 0.0, score);
  r.verification.degenerate = degenerate;
  return r;
}

TEST(JudgeRules, IcpIsKeptOnlyWhenTheCheckPrefersIt) {
  const PipelineConfig config;
  const RegistrationResult estimate = Estimate(true, 0.5, 20);
  const Transform near = testing::ShiftedAlongX(0.03);
  // Scores at least as well and keeps its evidence: kept.
  EXPECT_EQ(JudgeRefinement(estimate, RefinedTo(estimate, near, true, 0.6), 20, config, {}).kept,
            Refinement::kKept);
  EXPECT_EQ(JudgeRefinement(estimate, RefinedTo(estimate, near, true, 0.5), 20, config, {}).kept,
            Refinement::kKept);
  // The scans agree less after it: the estimate stays.
  EXPECT_EQ(JudgeRefinement(estimate, RefinedTo(estimate, near, true, 0.49), 20, config, {}).kept,
            Refinement::kScoresLower);
}

TEST(JudgeRules, IcpFromAnAcceptedEstimateKeepsHalfItsInliers) {
  const PipelineConfig config;  // refine.min_kept_inlier_fraction 0.5
  const RegistrationResult accepted = Estimate(true, 0.5, 20);
  const RegistrationResult better = RefinedTo(accepted, testing::ShiftedAlongX(0.4), true, 0.7);
  Refinement r = JudgeRefinement(accepted, better, 9, config, {});
  EXPECT_EQ(r.kept, Refinement::kLeftItsEvidence);
  EXPECT_EQ(r.kept_needed, 10.0);
  EXPECT_EQ(r.gate_m, config.refine.max_distance_coarse_m);
  EXPECT_FALSE(r.another_pose_passes);  // the method's own estimate: no floor, no such rule
  EXPECT_EQ(JudgeRefinement(accepted, better, 10, config, {}).kept, Refinement::kKept);
}

// Under an estimate the check refused, the correspondences are no evidence (repeated cabinet
// fronts 8 deg off, from which ICP reaches the truth): the check alone judges ICP; except where
// the refined pose is degenerate (a wall lets ICP slide and still pass).
TEST(JudgeRules, IcpFromARefusedEstimateIsJudgedByTheCheckAlone) {
  PipelineConfig config;
  config.refine.min_kept_inlier_fraction = 0.5;
  const RegistrationResult refused = Estimate(false, 0.1, 20);
  EXPECT_EQ(JudgeRefinement(refused, RefinedTo(refused, testing::ShiftedAlongX(0.5), true, 0.6), 0,
                            config, {})
                .kept,
            Refinement::kKept);
  EXPECT_EQ(
      JudgeRefinement(refused, RefinedTo(refused, testing::ShiftedAlongX(0.5), true, 0.6, true), 0,
                      config, {})
          .kept,
      Refinement::kLeftItsEvidence);
}

// The extra sources' floor (KeptEvidence): the object centroids keep the kept fraction even under
// a refused estimate (ICP from their refused estimate travelled 1.2-1.4 m into a wrong pose the
// check accepted); the point sources keep at least four, checked or not (ICP from a geometry
// estimate that kept 1 of its inliers went 176 deg wrong). hypotheses.refine_keeps_evidence off
// drops both.
TEST(JudgeRules, AnExtraSourcesRefinementKeepsItsFloor) {
  const PipelineConfig config;
  const RegistrationResult refused = Estimate(false, 0.1, 10);
  const RegistrationResult refined = RefinedTo(refused, testing::ShiftedAlongX(1.3), true, 0.4);
  const KeptEvidence centroids{/*fraction_always=*/true, /*min_kept=*/0};
  const KeptEvidence points{/*fraction_always=*/false, /*min_kept=*/4};
  EXPECT_EQ(JudgeRefinement(refused, refined, 4, config, centroids).kept,
            Refinement::kLeftItsEvidence);
  EXPECT_EQ(JudgeRefinement(refused, refined, 5, config, centroids).kept, Refinement::kKept);
  EXPECT_EQ(JudgeRefinement(refused, refined, 3, config, points).kept,
            Refinement::kLeftItsEvidence);
  EXPECT_EQ(JudgeRefinement(refused, refined, 4, config, points).kept, Refinement::kKept);
  PipelineConfig off = config;
  off.hypotheses.refine_keeps_evidence = false;
  EXPECT_EQ(JudgeRefinement(refused, refined, 0, off, centroids).kept, Refinement::kKept);
  EXPECT_EQ(JudgeRefinement(refused, refined, 0, off, points).kept, Refinement::kKept);
}

// An extra source's accepted estimate whose refinement leaves its evidence for another pose the
// check accepts too, farther apart than ICP's widest gate: the check cannot choose, so the
// estimate is not valid (a geometry estimate 179 deg off scored 0.205, ICP's pose 76 cm away
// 0.203). Nearer, or with the refined pose refused, or for the method's own estimate, it stays.
TEST(JudgeRules, AnEstimateWhoseRefinementIsAnotherAcceptedPoseIsNotValid) {
  const PipelineConfig config;
  const double coarse = config.refine.max_distance_coarse_m;
  const KeptEvidence points{false, 4};
  const RegistrationResult accepted = Estimate(true, 0.205, 8);
  Refinement r = JudgeRefinement(
      accepted, RefinedTo(accepted, testing::ShiftedAlongX(2 * coarse), true, 0.203), 1, config,
      points);
  EXPECT_EQ(r.kept, Refinement::kLeftItsEvidence);
  EXPECT_TRUE(r.another_pose_passes);
  EXPECT_NEAR(r.apart_m, 2 * coarse, 1e-9);
  r = JudgeRefinement(accepted,
                      RefinedTo(accepted, testing::ShiftedAlongX(0.9 * coarse), true, 0.203), 1,
                      config, points);
  EXPECT_FALSE(r.another_pose_passes);
  r = JudgeRefinement(accepted,
                      RefinedTo(accepted, testing::ShiftedAlongX(2 * coarse), false, 0.203), 1,
                      config, points);
  EXPECT_FALSE(r.another_pose_passes);
  r = JudgeRefinement(accepted,
                      RefinedTo(accepted, testing::ShiftedAlongX(2 * coarse), true, 0.203), 1,
                      config, {});
  EXPECT_FALSE(r.another_pose_passes);
}

TEST(JudgeRules, AValidResultBeyondThePriorsToleranceIsNotValid) {
  Stand s;
  s.prior = MotionPrior{Transform::Identity(), 15.0, 0.30};
  const Judge judge = s.judge();
  // Within the tolerance: unchanged.
  RegistrationResult r = Counted(true);
  r.T_target_source = testing::TurnedAboutZ(10) * testing::ShiftedAlongX(0.2);
  judge.ApplyPrior(&r);
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.outside_prior);
  // Turned beyond it: not valid, the rotation as the refusal's measure.
  r = Counted(true);
  r.T_target_source = testing::TurnedAboutZ(40);
  judge.ApplyPrior(&r);
  EXPECT_FALSE(r.valid);
  EXPECT_TRUE(r.outside_prior);
  EXPECT_EQ(r.refusal.test, RefusalTest::kOutsidePrior);
  EXPECT_NEAR(r.refusal.measured, 40.0, 1e-6);
  EXPECT_EQ(r.refusal.threshold, 15.0);
  // Turned within, moved beyond: the translation (m).
  r = Counted(true);
  r.T_target_source = testing::TurnedAboutZ(5) * testing::ShiftedAlongX(0.5);
  judge.ApplyPrior(&r);
  EXPECT_FALSE(r.valid);
  EXPECT_NEAR(r.refusal.measured, 0.5, 1e-6);
  EXPECT_EQ(r.refusal.threshold, 0.30);
  // An invalid result keeps its own refusal; without a prior nothing changes.
  r = Counted(false);
  r.T_target_source = testing::TurnedAboutZ(90);
  judge.ApplyPrior(&r);
  EXPECT_EQ(r.refusal.test, RefusalTest::kFewInliers);
  EXPECT_FALSE(r.outside_prior);
  Stand none;
  r = Counted(true);
  r.T_target_source = testing::TurnedAboutZ(90);
  none.judge().ApplyPrior(&r);
  EXPECT_TRUE(r.valid);
}

Judged Passed(double rho, bool degenerate) {
  Judged j;
  j.result = Counted(true);
  j.result.verification = Checked(true, 0.3, 0.02, 0.3);
  j.result.verification.brightness_rank_correlation = rho;
  j.result.verification.degenerate = degenerate;
  j.result.verification.probe_contradicted = 0.01;
  return j;
}

// A source whose correspondences come from no image (geometry, centroids) needs the images to
// agree where the depth does: two rooms' floors and walls lined up passed the check with a rank
// correlation of 0.31. A source too weak for degenerate geometry is refused there.
TEST(JudgeRules, ASourcesOwnRefusals) {
  const PipelineConfig config;  // hypotheses.min_brightness_rank_correlation 0.4
  Judged j = Passed(0.31, false);
  RefuseForTheSource(false, /*images_must_agree=*/true, false, config, &j);
  EXPECT_FALSE(j.result.valid);
  EXPECT_EQ(j.result.refusal.test, RefusalTest::kImagesDisagree);
  EXPECT_EQ(j.result.refusal.measured, 0.31);
  EXPECT_EQ(j.result.refusal.threshold, config.hypotheses.min_brightness_rank_correlation);
  EXPECT_FALSE(j.refusal.empty());
  // Agreeing images, no colour to tell (NaN), or a source that matched images: it stays valid.
  for (const double rho : {0.45, std::numeric_limits<double>::quiet_NaN()}) {
    j = Passed(rho, false);
    RefuseForTheSource(false, true, false, config, &j);
    EXPECT_TRUE(j.result.valid) << rho;
  }
  j = Passed(0.31, false);
  RefuseForTheSource(false, false, false, config, &j);
  EXPECT_TRUE(j.result.valid);
  EXPECT_TRUE(j.refusal.empty());
  // Degenerate geometry.
  j = Passed(0.9, true);
  RefuseForTheSource(/*refuse_degenerate=*/true, false, false, config, &j);
  EXPECT_FALSE(j.result.valid);
  EXPECT_EQ(j.result.refusal.test, RefusalTest::kDegenerate);
  EXPECT_EQ(j.result.refusal.measured, 0.01);
  EXPECT_EQ(j.result.refusal.threshold, config.verify.min_probe_contradicted);
  j = Passed(0.9, false);
  RefuseForTheSource(true, false, false, config, &j);
  EXPECT_TRUE(j.result.valid);
  // An invalid candidate keeps its own refusal.
  j = Passed(0.1, true);
  j.result.valid = false;
  j.result.refusal = {RefusalTest::kLowOverlap, 0.05, 0.1};
  RefuseForTheSource(true, true, false, config, &j);
  EXPECT_EQ(j.result.refusal.test, RefusalTest::kLowOverlap);
}

}  // namespace
}  // namespace zeroreg
