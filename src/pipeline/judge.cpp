#include "pipeline/judge.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "estimate/max_clique.hpp"
#include "estimate/rigid_ransac.hpp"
#include "eval/metrics.hpp"

namespace zeroreg {
namespace {

// Decides the verdict from the estimator's counts (RansacConfig documents the thresholds).
void DecideVerdict(const RansacConfig& config, RegistrationResult* r) {
  r->valid = false;
  // A new verdict: a result copied from another (the fallback from the method's) does not keep
  // the other's ApplyPrior flag.
  r->outside_prior = false;
  std::ostringstream why;
  Refusal& no = r->refusal;
  no = {};
  if (r->num_correspondences < 3) {
    no = {RefusalTest::kFewCorrespondences, static_cast<double>(r->num_correspondences), 3.0};
    why << "only " << r->num_correspondences
        << " 3D correspondences; at least 3 are needed to estimate a rigid transform";
  } else if (r->num_inliers < config.min_inliers) {
    no = {RefusalTest::kFewInliers, static_cast<double>(r->num_inliers),
          static_cast<double>(config.min_inliers)};
    why << "only " << r->num_inliers << " RANSAC inliers of " << r->num_correspondences
        << " correspondences (need at least " << config.min_inliers << ")";
  } else if (r->inlier_spread_m < config.min_inlier_spread_m) {
    no = {RefusalTest::kInliersOnALine, r->inlier_spread_m, config.min_inlier_spread_m};
    why << "the " << r->num_inliers << " inliers lie almost on a line (spread "
        << r->inlier_spread_m << " m across it, need " << config.min_inlier_spread_m
        << " m): the rotation about it is undetermined";
  } else if (r->inlier_ratio < config.min_inlier_ratio) {
    no = {RefusalTest::kLowInlierRatio, r->inlier_ratio, config.min_inlier_ratio};
    why << "inlier ratio " << r->inlier_ratio << " is below " << config.min_inlier_ratio << " ("
        << r->num_inliers << " of " << r->num_correspondences << ")";
  } else {
    r->valid = true;
    why << r->num_inliers << " of " << r->num_correspondences << " correspondences agree within "
        << config.inlier_threshold_m << " m";
  }
  r->reason = why.str();
}

// Standard deviation of the inliers' target points along their second principal axis: near zero
// when the inliers lie on a line, about which the rotation is then undetermined.
double InlierSpread(const RegistrationResult& r) {
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < r.correspondences.size(); ++i) {
    if (r.is_inlier[i]) points.push_back(r.correspondences[i].target);
  }
  if (points.size() < 3) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) covariance += (p - mean) * (p - mean).transpose();
  covariance /= static_cast<double>(points.size());
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();  // ascending
  return std::sqrt(std::max(0.0, eigenvalues(1)));
}

}  // namespace

// RANSAC (or the clique estimator) on C_point, then the count verdict (§3.4, after Eq. 4).
void Judge::Estimate(std::vector<Correspondence> correspondences, const PipelineConfig& config,
                     RegistrationResult* r) const {
  r->correspondences = std::move(correspondences);
  r->num_correspondences = static_cast<int>(r->correspondences.size());
  std::vector<Eigen::Vector3d> src, tgt;
  std::vector<float> scores;
  src.reserve(r->correspondences.size());
  tgt.reserve(r->correspondences.size());
  for (const Correspondence& c : r->correspondences) {
    src.push_back(c.source);
    tgt.push_back(c.target);
    scores.push_back(c.score);
  }
  // ransac.estimator: RANSAC (the paper's) or the maximum-clique estimator.
  const RansacResult ransac = EstimateRigid(src, tgt, scores, config.ransac, config.seed);
  r->T_target_source = ransac.T_target_source;
  r->is_inlier = ransac.is_inlier;
  r->num_inliers = ransac.num_inliers;
  r->inlier_rmse = ransac.inlier_rmse;
  r->ransac_iterations = ransac.iterations;
  r->inlier_ratio = r->num_correspondences > 0
                        ? static_cast<double>(ransac.num_inliers) / r->num_correspondences
                        : 0.0;
  r->inlier_spread_m = InlierSpread(*r);
  r->valid = false;
  DecideVerdict(config.ransac, r);
  r->count_test_passed = r->valid;
}

namespace {

// Inlier flags, count, ratio, RMSE and spread of the correspondences under r->T_target_source.
void UpdateInlierStats(double threshold_m, RegistrationResult* r) {
  const Eigen::Matrix3d R = r->T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = r->T_target_source.topRightCorner<3, 1>();
  r->is_inlier.assign(r->correspondences.size(), false);
  r->num_inliers = 0;
  double sum_sq = 0;
  for (size_t i = 0; i < r->correspondences.size(); ++i) {
    const Correspondence& c = r->correspondences[i];
    const double d2 = (R * c.source + t - c.target).squaredNorm();
    if (d2 < threshold_m * threshold_m) {
      r->is_inlier[i] = true;
      ++r->num_inliers;
      sum_sq += d2;
    }
  }
  r->inlier_ratio = r->correspondences.empty()
                        ? 0.0
                        : static_cast<double>(r->num_inliers) / r->correspondences.size();
  r->inlier_rmse = r->num_inliers > 0 ? std::sqrt(sum_sq / r->num_inliers) : 0.0;
  r->inlier_spread_m = InlierSpread(*r);
}

// How many of r's inlier correspondences lie within distance_m of each other under T.
int CountWithin(const RegistrationResult& r, const Transform& T, double distance_m) {
  int count = 0;
  for (size_t i = 0; i < r.correspondences.size(); ++i) {
    if (!r.is_inlier[i]) continue;
    const Correspondence& c = r.correspondences[i];
    const Eigen::Vector3d moved = (T * c.source.homogeneous()).head<3>();
    if ((moved - c.target).norm() < distance_m) ++count;
  }
  return count;
}

// Which of the check's tests refused it (the order VerifyRegistration decides in); kNone when
// it passed.
Refusal CheckRefusal(const VerificationResult& v, const VerifyConfig& config) {
  if (v.passed) return {};
  const int samples = std::min(v.source_samples, v.target_samples);
  if (samples < config.min_points) {
    return {RefusalTest::kLittleDepth, static_cast<double>(samples),
            static_cast<double>(config.min_points)};
  }
  if (v.overlap < config.min_overlap) {
    return {RefusalTest::kLowOverlap, v.overlap, config.min_overlap};
  }
  return {RefusalTest::kFreeSpaceViolation, v.violation, config.max_violation};
}

}  // namespace

const char* RefusalTestName(RefusalTest test) {
  switch (test) {
    case RefusalTest::kNone:
      return "";
    case RefusalTest::kFewCorrespondences:
      return "few_correspondences";
    case RefusalTest::kFewInliers:
      return "few_inliers";
    case RefusalTest::kInliersOnALine:
      return "inliers_on_a_line";
    case RefusalTest::kLowInlierRatio:
      return "low_inlier_ratio";
    case RefusalTest::kLittleDepth:
      return "little_depth";
    case RefusalTest::kLowOverlap:
      return "low_overlap";
    case RefusalTest::kFreeSpaceViolation:
      return "free_space_violation";
    case RefusalTest::kOutsidePrior:
      return "outside_prior";
    case RefusalTest::kDegenerate:
      return "degenerate";
    case RefusalTest::kImagesDisagree:
      return "images_disagree";
    case RefusalTest::kAnotherPosePasses:
      return "another_pose_passes";
    case RefusalTest::kAmbiguous:
      return "ambiguous";
  }
  return "";
}

std::string DescribeRefusal(const Refusal& r) {
  const char* what = "";
  switch (r.test) {
    case RefusalTest::kNone:
      return "";
    case RefusalTest::kFewCorrespondences:
      what = "too few correspondences: %g (need %g)";
      break;
    case RefusalTest::kFewInliers:
      what = "too few inliers: %g (need %g)";
      break;
    case RefusalTest::kInliersOnALine:
      what = "inliers on a line: spread %g m (need %g m)";
      break;
    case RefusalTest::kLowInlierRatio:
      what = "inlier ratio %g below %g";
      break;
    case RefusalTest::kLittleDepth:
      what = "too little depth to verify: %g samples (need %g)";
      break;
    case RefusalTest::kLowOverlap:
      what = "the scans do not agree: overlap %g (need %g)";
      break;
    case RefusalTest::kFreeSpaceViolation:
      what = "the scans contradict each other: free-space violations %g (allowed %g)";
      break;
    case RefusalTest::kOutsidePrior:
      what = "outside the motion prior: %g (tolerance %g)";
      break;
    case RefusalTest::kDegenerate:
      what = "degenerate geometry: %g of the surface contradicted by a slide (need %g)";
      break;
    case RefusalTest::kImagesDisagree:
      what = "the images disagree where the depth agrees: rank correlation %g (need %g)";
      break;
    case RefusalTest::kAnotherPosePasses:
      what = "another pose passes the check: %g m away (ICP's widest gate %g m)";
      break;
    case RefusalTest::kAmbiguous:
      what = "ambiguous: two poses fit, %g m apart (the check tells poses apart beyond %g m)";
      break;
  }
  char text[200];
  std::snprintf(text, sizeof(text), what, r.measured, r.threshold);
  return text;
}

// With verification on, the count test of DecideVerdict is the evidence that an estimate exists,
// and `valid` additionally needs the scans to agree under it.
void Judge::Check(const PipelineConfig& config, const std::string& name,
                  RegistrationResult* r) const {
  if (!config.verify.enabled) return;
  const bool evidence = r->count_test_passed;
  r->verification = VerifyRegistration(source_.scan, source_.surface, target_.scan, target_.surface,
                                       r->T_target_source, config.verify, config.depth);
  r->candidates.push_back(
      {name, r->T_target_source, r->verification.score, evidence && r->verification.passed, false});
  if (!evidence) return;  // the count reason stands
  r->valid = r->verification.passed;
  r->refusal = CheckRefusal(r->verification, config.verify);
  r->reason = r->verification.reason + " (" + r->reason + ")";
}

// Coarse-to-fine point-to-plane ICP from the estimate. The refined transform is kept only when
// the geometric check scores it at least as well as the estimate it started from and
// at least half of the estimate's inlier correspondences stay within its coarse gate: ICP fits all
// of both scans' geometry, so where it slides (along a plane, pulled by surface one scan sees
// alone) the scans agree less or the image evidence is left behind, and the estimate stays. Without
// verification ICP is kept. `rule`: what an extra source's refinement must keep besides.
void Judge::Refine(const PipelineConfig& pipeline, RegistrationResult* r, KeptEvidence rule) const {
  const RefineConfig& config = pipeline.refine;
  IcpAnchors anchors;
  for (size_t i = 0; i < r->correspondences.size(); ++i) {
    if (!r->is_inlier[i]) continue;
    anchors.source.push_back(r->correspondences[i].source);
    anchors.target.push_back(r->correspondences[i].target);
  }
  // Where the check found the geometry degenerate, the correspondences are what fixes the open
  // motion, so they hold every stage: fitting depth alone, the fine stages slid a wall-and-floor
  // pair 68 cm along it.
  std::vector<IcpStage> stages = IcpSchedule(config, pipeline.depth);
  if (r->verification.degenerate) {
    for (IcpStage& stage : stages) {
      stage.anchor_weight = std::max(stage.anchor_weight, config.anchor_weight_coarse);
    }
  }
  const IcpResult icp = RefinePointToPlane(source_.icp, target_.icp, r->T_target_source, stages,
                                           anchors, pipeline.threads);
  const double moved_m = TranslationErrorM(icp.T_target_source, r->T_target_source);
  const double turned_deg = RotationErrorDeg(icp.T_target_source, r->T_target_source);
  RegistrationResult refined = *r;
  refined.T_target_source = icp.T_target_source;
  UpdateInlierStats(pipeline.ransac.inlier_threshold_m, &refined);
  char note[320];
  if (pipeline.verify.enabled) {
    refined.verification =
        VerifyRegistration(source_.scan, source_.surface, target_.scan, target_.surface,
                           refined.T_target_source, pipeline.verify, pipeline.depth);
    refined.candidates.push_back({PathName(r->path) + " icp", refined.T_target_source,
                                  refined.verification.score, refined.verification.passed, false});
    r->candidates = refined.candidates;
    // A refinement keeps the evidence it started from: most of the correspondences that
    // supported the estimate stay within ICP's own pull-in range (the coarse gate; at the 5 cm
    // inlier distance correct 5 cm corrections were refused). ICP that left them moved 25-70 cm
    // into another minimum of the depth fit: a new registration the images contradict. The test
    // applies to an estimate the check accepted: under a refused one the correspondences are no
    // evidence (repeated cabinet fronts 8-10 deg off, from which ICP reaches the truth), so the
    // check judges ICP alone; except in degenerate geometry, where it cannot (a wall lets ICP
    // slide a metre and still pass). The extra sources are held to more (KeptEvidence): a few
    // centroids pin no surface, and ICP from their refused estimate travelled 1.2-1.4 m into a
    // wrong pose the check accepted, so their refinement keeps its evidence always.
    const bool keep_evidence = pipeline.hypotheses.refine_keeps_evidence;
    const bool evidence_needed = r->verification.passed || refined.verification.degenerate ||
                                 (keep_evidence && rule.fraction_always);
    const double gate_m =
        std::max(config.max_distance_coarse_m, pipeline.ransac.inlier_threshold_m);
    const int kept = CountWithin(*r, icp.T_target_source, gate_m);
    // Three correspondences agree with some motion whenever their pairwise distances do: an extra
    // source's refinement keeps at least four of them, checked or not.
    const double kept_floor = keep_evidence ? static_cast<double>(rule.min_kept) : 0.0;
    const double kept_needed =
        evidence_needed ? std::max(config.min_kept_inlier_fraction * r->num_inliers, kept_floor)
                        : kept_floor;
    if (kept < kept_needed) {
      std::snprintf(note, sizeof(note),
                    "; ICP refinement rejected: only %d of the %d correspondences that support "
                    "the estimate stay within %.2f m of it (it would move %.1f cm, %.2f deg)",
                    kept, r->num_inliers, gate_m, moved_m * 100, turned_deg);
      r->reason += note;
      // An extra source's estimate the check accepted, whose refinement left its evidence for
      // another pose the check accepts as well, farther than ICP's widest gate: the check cannot
      // choose between two poses it accepts (as for hypotheses.always), and the estimate rests on
      // a few correspondences of a source that runs because the method's own estimate failed,
      // counted without an inlier ratio (hypotheses.min_inlier_ratio). Neither is valid (a
      // geometry estimate 179 deg off scored 0.205, ICP's pose 76 cm away 0.203).
      if (keep_evidence && rule.min_kept > 0 && r->valid && refined.verification.passed &&
          Disagree(EstimateDisplacementRms(*r, refined), pipeline)) {
        r->valid = false;
        r->refusal = {RefusalTest::kAnotherPosePasses, EstimateDisplacementRms(*r, refined),
                      pipeline.refine.max_distance_coarse_m};
        r->reason +=
            "; not valid: the check accepts that pose as well, so the scans do not determine "
            "the transform";
      }
      return;
    }
    if (refined.verification.score < r->verification.score) {
      std::snprintf(note, sizeof(note),
                    "; ICP refinement rejected: the scans agree less after it (score %.3f < "
                    "%.3f; it would move %.1f cm, %.2f deg)",
                    refined.verification.score, r->verification.score, moved_m * 100, turned_deg);
      r->reason += note;
      return;
    }
    refined.valid = refined.verification.passed;
    refined.refusal = CheckRefusal(refined.verification, pipeline.verify);
    refined.outside_prior = false;  // a new verdict (ApplyPrior decides it again)
    refined.reason = refined.verification.reason;
  }
  std::snprintf(note, sizeof(note),
                "; refined by ICP (fitness %.2f, moved %.1f cm, %.2f deg; %d of %d "
                "correspondences within %.2f m of the refined transform)",
                icp.fitness, moved_m * 100, turned_deg, refined.num_inliers,
                refined.num_correspondences, pipeline.ransac.inlier_threshold_m);
  refined.reason += note;
  *r = std::move(refined);
}

PriorDistance DistanceFromPrior(const MotionPrior& prior, const Transform& T) {
  PriorDistance d;
  d.turned_deg = RotationErrorDeg(T, prior.T_target_source);
  d.moved_m = TranslationErrorM(T, prior.T_target_source);
  d.beyond = d.turned_deg > prior.max_rotation_deg || d.moved_m > prior.max_translation_m;
  return d;
}

// MotionPrior: a valid result farther from the prior than its tolerance is made invalid, with
// the distance in the reason. Applied wherever a verdict is reached, so that the fallback and the
// extra hypotheses still run when the method's own estimate lies outside the prior.
void Judge::ApplyPrior(RegistrationResult* r) const {
  if (!prior_ || !r->valid) return;
  const MotionPrior* prior = &*prior_;
  const PriorDistance d = DistanceFromPrior(*prior, r->T_target_source);
  if (!d.beyond) return;
  r->valid = false;
  r->outside_prior = true;
  r->refusal = d.turned_deg > prior->max_rotation_deg
                   ? Refusal{RefusalTest::kOutsidePrior, d.turned_deg, prior->max_rotation_deg}
                   : Refusal{RefusalTest::kOutsidePrior, d.moved_m, prior->max_translation_m};
  char note[200];
  std::snprintf(note, sizeof(note),
                "; not valid: %.1f deg and %.1f cm from the motion prior (tolerance %.1f deg, "
                "%.1f cm)",
                d.turned_deg, d.moved_m * 100, prior->max_rotation_deg,
                prior->max_translation_m * 100);
  r->reason += note;
}

Judged Judge::Full(Proposal p, StageTimer* timer) const {
  const auto mark = [timer](const char* stage) {
    if (timer != nullptr) timer->Mark(stage);
  };
  Judged out;
  RegistrationResult& r = out.result;
  r.path = p.path;
  r.rendered_view = p.rendered_view;
  const PipelineConfig& e = p.effective;
  if (p.pose) {
    // A pose without correspondences (the motion prior): its own evidence, judged by the check.
    r.T_target_source = *p.pose;
    r.count_test_passed = true;
    r.reason = "started from the motion prior";
  } else {
    Estimate(std::move(p.correspondences), e, &r);
    mark("estimate");
  }
  Check(e, p.check_name.empty() ? PathName(p.path) : p.check_name, &r);
  ApplyPrior(&r);
  mark("verify");
  out.valid_before_icp = r.valid;
  if (e.refine.enabled && r.count_test_passed) {
    if (timer != nullptr) timer->Restart();
    Refine(e, &r, p.keep);
    mark("refine");
  }
  ApplyPrior(&r);
  // A pose source's start moved by ICP is named so ("prior" -> "prior icp").
  if (p.pose && r.T_target_source != *p.pose) r.path.moved_by_icp = true;
  const HypothesesConfig& h = config_.hypotheses;
  if (p.refuse_degenerate && r.valid && r.verification.degenerate) {
    r.valid = false;
    r.refusal = {RefusalTest::kDegenerate, r.verification.probe_contradicted,
                 config_.verify.min_probe_contradicted};
    out.refusal = "refused: degenerate geometry";
    r.reason += p.pose ? "; not valid: the geometry is degenerate and no correspondence fixes the "
                         "motion it leaves open"
                       : "; refused: the geometry is degenerate and this source's correspondences "
                         "are too weak to fix the open motion";
  }
  const double rho = r.verification.brightness_rank_correlation;
  if (p.images_must_agree && r.valid && std::isfinite(rho) &&
      rho < h.min_brightness_rank_correlation) {
    r.valid = false;
    r.refusal = {RefusalTest::kImagesDisagree, rho, h.min_brightness_rank_correlation};
    out.refusal = "refused: the images disagree where the depth agrees";
    char note[200];
    std::snprintf(note, sizeof(note),
                  "; refused: the images disagree where the depth agrees (rank correlation of "
                  "their brightness %.2f, need %.2f)",
                  rho, h.min_brightness_rank_correlation);
    r.reason += note;
  }
  return out;
}

void Adopt(RegistrationResult winner, RegistrationResult* result) {
  winner.source_objects = std::move(result->source_objects);
  winner.target_objects = std::move(result->target_objects);
  winner.object_matches = std::move(result->object_matches);
  winner.rejected_object_matches = result->rejected_object_matches;
  winner.num_keypoints_source = result->num_keypoints_source;
  winner.num_keypoints_target = result->num_keypoints_target;
  *result = std::move(winner);
}

bool Disagree(double apart_m, const PipelineConfig& config) {
  return apart_m > config.refine.max_distance_coarse_m;
}

double EstimateDisplacementRms(const RegistrationResult& a, const RegistrationResult& b) {
  double sum = 0.0;
  size_t n = 0;
  const Eigen::Matrix3d Ra = a.T_target_source.topLeftCorner<3, 3>();
  const Eigen::Matrix3d Rb = b.T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d ta = a.T_target_source.topRightCorner<3, 1>();
  const Eigen::Vector3d tb = b.T_target_source.topRightCorner<3, 1>();
  for (const RegistrationResult* r : {&a, &b}) {
    for (const Correspondence& c : r->correspondences) {
      sum += ((Ra * c.source + ta) - (Rb * c.source + tb)).squaredNorm();
      ++n;
    }
  }
  return n == 0 ? 0.0 : std::sqrt(sum / static_cast<double>(n));
}

double PointDisplacementRms(const std::vector<SurfacePoint>* surface, const Transform& a,
                            const Transform& b) {
  if (surface == nullptr || surface->empty()) return 0.0;
  double sum = 0.0;
  for (const SurfacePoint& s : *surface) {
    const Eigen::Vector3d& p = s.point;
    sum += ((a * p.homogeneous()).head<3>() - (b * p.homogeneous()).head<3>()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(surface->size()));
}

}  // namespace zeroreg
