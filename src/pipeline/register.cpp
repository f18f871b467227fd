#include "zeroreg/register.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "estimate/icp.hpp"
#include "estimate/max_clique.hpp"
#include "estimate/rigid_ransac.hpp"
#include "eval/metrics.hpp"
#include "features/feature_extractor.hpp"
#include "inference/onnx_model.hpp"
#include "io/text_parsing.hpp"
#include "object_match/result_support.hpp"
#include "parallel/run_both.hpp"
#include "pipeline/hypotheses.hpp"
#include "pipeline/image_source.hpp"
#include "pipeline/object_correspondences.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "verify/verify.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg {

// What Pipeline::Prepare keeps of one scan.
struct PreparedScan::Data {
  std::uint64_t pipeline_id = 0;  // the Pipeline that made it (its config decided all of it)
  Scan scan;
  std::shared_ptr<const PerceivedScan> perceived;  // features, detections, masks, objects
  std::vector<SurfacePoint> surface;               // verification samples (verify.enabled)
  IcpGeometry icp;                                 // ICP clouds per resolution (refine.enabled)
  std::vector<StageTime> timings;
  std::size_t memory_bytes = 0;
  // hypotheses.turned_images: the features of the turned colour images, made the first time a
  // pair with this scan as its source needs them (most scans never do), then shared by every such
  // pair (ExtractTurnedFeatures).
  mutable std::once_flag turned_once;
  mutable TurnedFeatures turned;
  // What `turned` holds once made (MemoryBytes includes it from then on; 0 before).
  mutable std::atomic<std::size_t> turned_bytes{0};
};

PreparedScan::PreparedScan() = default;
PreparedScan::~PreparedScan() = default;
PreparedScan::PreparedScan(const PreparedScan&) = default;
PreparedScan& PreparedScan::operator=(const PreparedScan&) = default;
bool PreparedScan::empty() const { return data_ == nullptr; }
const Scan& PreparedScan::scan() const {
  if (!data_) throw std::logic_error("PreparedScan::scan() called on an empty prepared scan");
  return data_->scan;
}
const std::vector<StageTime>& PreparedScan::timings() const {
  static const std::vector<StageTime> kNone;
  return data_ ? data_->timings : kNone;
}
std::size_t PreparedScan::MemoryBytes() const {
  return data_ ? data_->memory_bytes + data_->turned_bytes.load() : 0;
}

namespace {

// The paths of a result made from the motion prior (ComesFromMotionPrior).
constexpr const char* kPriorPath = "prior";
constexpr const char* kPriorIcpPath = "prior icp";

using Prepared = PreparedScan::Data;

// The core trusts its inputs; this is the boundary check for scans built by callers (C++ or
// Python), with messages that name the scan and view.
void CheckScan(const Scan& scan, const std::string& role) {
  const std::string where = role + " scan '" + scan.name + "'";
  if (scan.views.empty()) {
    throw MakeInputError(where, "has no views; expected at least one posed RGB-D view");
  }
  for (size_t i = 0; i < scan.views.size(); ++i) {
    const View& v = scan.views[i];
    const std::string view_where = where + " view " + std::to_string(i) + " (" + v.name + ")";
    if (v.color.empty() || v.color.type() != CV_8UC3) {
      throw MakeInputError(view_where, "colour image is empty or not 8-bit 3-channel");
    }
    if (v.depth.empty() || v.depth.type() != CV_32FC1) {
      throw MakeInputError(view_where, "depth image is empty or not float32 metres");
    }
    if (v.color.size() != v.depth.size()) {
      std::ostringstream s;
      s << "colour is " << v.color.cols << "x" << v.color.rows << " but depth is " << v.depth.cols
        << "x" << v.depth.rows << "; expected the same size";
      throw MakeInputError(view_where, s.str());
    }
    if (!(v.intrinsics.fx > 0 && v.intrinsics.fy > 0)) {
      throw MakeInputError(view_where, "intrinsics fx/fy must be positive");
    }
  }
}

// Decides the verdict from the estimator's counts (RansacConfig documents the thresholds).
void DecideVerdict(const RansacConfig& config, RegistrationResult* r) {
  r->valid = false;
  // A new verdict: a result copied from another (the fallback from the method's) does not keep
  // the other's ApplyPrior flag.
  r->outside_prior = false;
  std::ostringstream why;
  if (r->num_correspondences < 3) {
    why << "only " << r->num_correspondences
        << " 3D correspondences; at least 3 are needed to estimate a rigid transform";
  } else if (r->num_inliers < config.min_inliers) {
    why << "only " << r->num_inliers << " RANSAC inliers of " << r->num_correspondences
        << " correspondences (need at least " << config.min_inliers << ")";
  } else if (r->inlier_spread_m < config.min_inlier_spread_m) {
    why << "the " << r->num_inliers << " inliers lie almost on a line (spread "
        << r->inlier_spread_m << " m across it, need " << config.min_inlier_spread_m
        << " m): the rotation about it is undetermined";
  } else if (r->inlier_ratio < config.min_inlier_ratio) {
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

// RANSAC on the correspondences, then the verdict (§3.4).
void Estimate(std::vector<Correspondence> correspondences, const PipelineConfig& config,
              RegistrationResult* r) {
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
  // ransac.estimator: RANSAC (the paper's) or the maximum-clique estimator (issue 12).
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

// Records the check of r->T_target_source as a candidate named `name` and folds it into the
// verdict: with verification on, the count test of DecideVerdict is the evidence that an estimate
// exists, and `valid` additionally needs the scans to agree under it.
void ApplyVerification(const Prepared& source, const Prepared& target, const PipelineConfig& config,
                       const std::string& name, RegistrationResult* r) {
  if (!config.verify.enabled) return;
  const bool evidence = r->count_test_passed;
  r->verification = VerifyRegistration(source.scan, source.surface, target.scan, target.surface,
                                       r->T_target_source, config.verify);
  r->candidates.push_back(
      {name, r->T_target_source, r->verification.score, evidence && r->verification.passed, false});
  if (!evidence) return;  // the count reason stands
  r->valid = r->verification.passed;
  r->reason = r->verification.reason + " (" + r->reason + ")";
}

// What ICP's refinement of an extra hypothesis (hypotheses.refine_keeps_evidence) must keep of
// the estimate's inliers within the gate of Refine, beyond the method's own test. Three
// correspondences agree with some motion whenever their pairwise distances do; a refined pose
// that keeps fewer than four of the estimate's rests on nothing but the check.
struct KeptEvidence {
  // The kept fraction (refine.min_kept_inlier_fraction) applies even where the check refused the
  // estimate: the object centroids, which pin no surface.
  bool fraction_always = false;
  // At least this many are kept, whether or not the check accepted the estimate (an accepted
  // estimate already keeps the fraction, at least 5 of the 10 RANSAC inliers by default, so the
  // floor decides for refused ones); 0 = no floor (the method's own estimate). With a floor, the
  // estimate is also not valid when its rejected refinement is a pose the check accepts too,
  // farther than ICP's widest gate (Refine). The other sources' refused estimates keep only this
  // floor: on repeated structure they are a few degrees off and ICP reaches the truth keeping a
  // small part of them (cabinet-gap3 0-3: 21 deg to 1.1 deg, 19 of 713 within 0.08 m), while ICP
  // from the geometry source's estimate that kept 1 of 261 went 176 deg wrong (redkitchen
  // 134 -> 765, co-visibility 2 %, scripts/bench-negatives.py).
  int min_kept = 0;
};

// Coarse-to-fine point-to-plane ICP from the estimate. The refined transform is kept only when
// the geometric check scores it at least as well as the estimate it started from (issue 10) and
// at least half of the estimate's inlier correspondences stay within its coarse gate: ICP fits all
// of both scans' geometry, so where it slides (along a plane, pulled by surface one scan sees
// alone) the scans agree less or the image evidence is left behind, and the estimate stays. Without
// verification ICP is kept.
// `rule`: what an extra hypothesis's refinement must keep besides (KeptEvidence).
void Refine(const Prepared& source, const Prepared& target, const PipelineConfig& pipeline,
            RegistrationResult* r, KeptEvidence rule = {}) {
  const RefineConfig& config = pipeline.refine;
  IcpAnchors anchors;
  for (size_t i = 0; i < r->correspondences.size(); ++i) {
    if (!r->is_inlier[i]) continue;
    anchors.source.push_back(r->correspondences[i].source);
    anchors.target.push_back(r->correspondences[i].target);
  }
  // Where the check found the geometry degenerate, the correspondences are what fixes the open
  // motion, so they hold every stage, not only the coarse one: the fine stages, fitting depth
  // alone, slid a HoloLens wall-and-floor pair 68 cm along it in 5 cm steps (hololens-gap5
  // 247-252).
  std::vector<IcpStage> stages = IcpSchedule(config);
  if (r->verification.degenerate) {
    for (IcpStage& stage : stages) {
      stage.anchor_weight = std::max(stage.anchor_weight, config.anchor_weight_coarse);
    }
  }
  const IcpResult icp = RefinePointToPlane(source.icp, target.icp, r->T_target_source, stages,
                                           anchors, pipeline.threads);
  const double moved_m = TranslationErrorM(icp.T_target_source, r->T_target_source);
  const double turned_deg = RotationErrorDeg(icp.T_target_source, r->T_target_source);
  RegistrationResult refined = *r;
  refined.T_target_source = icp.T_target_source;
  UpdateInlierStats(pipeline.ransac.inlier_threshold_m, &refined);
  char note[320];
  if (pipeline.verify.enabled) {
    refined.verification =
        VerifyRegistration(source.scan, source.surface, target.scan, target.surface,
                           refined.T_target_source, pipeline.verify);
    refined.candidates.push_back({r->path + " icp", refined.T_target_source,
                                  refined.verification.score, refined.verification.passed, false});
    r->candidates = refined.candidates;
    // A refinement keeps the evidence it started from: most of the correspondences that
    // supported the estimate stay within ICP's own pull-in range (the coarse gate) of the refined
    // transform. ICP that left them (moved 25-70 cm into another minimum of the depth fit, measured
    // on cabinet-gap3 and hololens-gap5) is a new registration the image evidence contradicts, not
    // a refinement. (Counting them at the 5 cm inlier distance instead rejected correct 5 cm
    // corrections on redkitchen-gap60: RANSAC's inliers sit up to 5 cm off its own estimate.)
    // The test applies to an estimate the check accepted. An estimate under which the scans
    // contradict each other has correspondences that are not evidence of anything (on
    // redkitchen-cross 471-866 and 490-858 they sit on repeated cabinet fronts, 8-10 deg off, and
    // ICP from there reaches the truth within 1.4-3.8 deg), so ICP's transform is judged by the
    // check alone, as any other hypothesis is; except where the check finds the geometry
    // degenerate: there it cannot judge alone (a HoloLens wall lets ICP slide a metre and still
    // pass, hololens-gap5 165-170), as for the extra sources (hypotheses.refuse_degenerate).
    // The extra hypotheses are held to more (hypotheses.refine_keeps_evidence, KeptEvidence):
    // a few object centroids 0.3 m apart pin no surface, so ICP from their refused estimate
    // starts blind; it travelled 1.2-1.4 m into a wrong pose the check accepted (hololens-cross
    // 49-368, 50-369, both detectors on every view). Their refinement keeps its evidence always,
    // each inlier within the distance it was counted at (0.3 m, wider than the gate). Every extra
    // source's refinement keeps at least four of its estimate's inliers, refused or not.
    const bool keep_evidence = pipeline.hypotheses.refine_keeps_evidence;
    const bool evidence_needed = r->verification.passed || refined.verification.degenerate ||
                                 (keep_evidence && rule.fraction_always);
    const double gate_m =
        std::max(config.max_distance_coarse_m, pipeline.ransac.inlier_threshold_m);
    const int kept = CountWithin(*r, icp.T_target_source, gate_m);
    // Three correspondences agree with some motion whenever their pairwise distances do, which
    // three object centroids at 0.3 m often do (hololens-cross 50-369: 3 of 20 kept, 43 deg off):
    // an extra hypothesis's refinement keeps at least four of them, checked or not.
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
      // counted without an inlier ratio (hypotheses.min_inlier_ratio). Neither is valid.
      // (redkitchen 299 <- 80, 6 % co-visible: the geometry source's estimate, 179 deg off,
      // scored 0.205 and ICP's pose 76 cm away 0.203; scripts/bench-negatives.py.)
      if (keep_evidence && rule.min_kept > 0 && r->valid && refined.verification.passed &&
          Disagree(EstimateDisplacementRms(*r, refined), pipeline)) {
        r->valid = false;
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

// Model files of the configured detector, verified against the repo's sha256 list.
// PicoDet: only the file of the configured engine (the verbatim export on ONNX Runtime, the
// Clip-rewritten copy on OpenCV DNN).
DetectorModelPaths ResolveDetectorModels(const DetectorConfig& config,
                                         const InferenceConfig& inference,
                                         const std::string& assets) {
  DetectorModelPaths paths;
  if (config.backend == "yolox" || config.backend == "ensemble") {
    paths.yolox_onnx = RequireAsset(assets, "yolox_nano_coco/yolox_nano.onnx");
    paths.yolox_classes = RequireAsset(assets, "yolox_nano_coco/coco_classes.txt");
  }
  if (config.backend == "picodet" || config.backend == "ensemble") {
    if (ResolveEngine(inference) == InferenceEngine::kOpenCv) {
      paths.picodet_opencv_onnx =
          RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.opencv.onnx");
    } else {
      paths.picodet_onnx = RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.onnx");
    }
    paths.picodet_classes = RequireAsset(assets, "picodet_s_416_coco/coco.names");
  }
  if (config.backend == "darknet") {
    paths.darknet_cfg = RequireAsset(assets, "yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.cfg");
    paths.darknet_weights =
        RequireAsset(assets, "yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.weights");
    paths.darknet_classes = RequireAsset(assets, "yolo_fastest_1.1_xl_coco/coco_classes.txt");
  }
  return paths;
}

// Whether any configured stage reads a model file (SIFT + file detections + no CLIP need none).
bool NeedsAssets(const PipelineConfig& c) {
  if (c.features.backend != "sift") return true;
  if (!c.method.object_level) return false;
  return c.detector.backend != "file" || c.method.clip || c.segmenter.backend == "sam";
}

// Heap bytes of one view's features: keypoints with their scores, descriptors, 3D points.
std::size_t LiftedFeaturesBytes(const LiftedFeatures& f) {
  return f.features.keypoints.size() * (sizeof(Eigen::Vector2f) + sizeof(float)) +
         static_cast<std::size_t>(f.features.descriptors.size()) * sizeof(float) +
         f.points.size() * sizeof(Eigen::Vector3d);
}

// Heap bytes of what a prepared scan holds (images, points, features, masks, clouds).
std::size_t PreparedBytes(const Prepared& p) {
  std::size_t bytes = p.scan.points.size() * sizeof(Eigen::Vector3d) +
                      p.scan.colors.size() * sizeof(Eigen::Vector3d);
  for (const View& v : p.scan.views) {
    bytes += v.color.total() * v.color.elemSize() + v.depth.total() * v.depth.elemSize();
  }
  for (const LiftedFeatures& f : p.perceived->view_features) bytes += LiftedFeaturesBytes(f);
  for (const ObjectObservation& o : p.perceived->objects.observations) {
    bytes += o.mask.total() * o.mask.elemSize() + o.points.size() * sizeof(Eigen::Vector3d);
  }
  for (const SceneObject& o : p.perceived->objects.objects) {
    bytes += o.points.size() * sizeof(Eigen::Vector3d);
  }
  for (const auto& rows : p.perceived->observation_rows) bytes += rows.size() * sizeof(int);
  bytes += p.surface.size() * sizeof(SurfacePoint) + p.icp.MemoryBytes();
  return bytes;
}

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// object_match.agree_with_result: a valid result keeps the object matches its transform T
// supports (TransformSupportsMatch; `points` are the matches' point matches, parallel to
// result->object_matches); the others are counted as rejected.
void KeepObjectMatchesThatMoveWith(const Transform& T, const std::vector<MatchMotion>& points,
                                   double threshold_m, RegistrationResult* result) {
  if (points.size() != result->object_matches.size()) return;
  std::vector<ObjectMatchSummary> kept;
  for (size_t i = 0; i < points.size(); ++i) {
    const ObjectMatchSummary& m = result->object_matches[i];
    if (TransformSupportsMatch(T, points[i], result->source_objects[m.source].points,
                               result->target_objects[m.target].points, threshold_m)) {
      kept.push_back(m);
    }
  }
  result->rejected_object_matches += static_cast<int>(result->object_matches.size() - kept.size());
  result->object_matches = std::move(kept);
}

// A prior that is not a rigid transform, or a tolerance that is not a positive number, is refused
// by name (InputError) rather than silently making every result invalid.
void CheckPrior(const std::optional<MotionPrior>& prior) {
  if (!prior) return;
  // The same test (and tolerances) as every pose file (ReadPoseFile): what reads as a pose is
  // accepted as a prior.
  detail::CheckRigid(prior->T_target_source, "motion prior T_target_source");
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(prior->max_rotation_deg) || !positive(prior->max_translation_m)) {
    std::ostringstream given;
    given << "max_rotation_deg " << prior->max_rotation_deg << ", max_translation_m "
          << prior->max_translation_m;
    throw MakeInputError("motion prior tolerance",
                         given.str() + ": expected positive numbers (degrees, metres)");
  }
}

// How far T is from the prior (rotation angle, deg; translation, m), and whether that is beyond
// its tolerance.
struct PriorDistance {
  double turned_deg = 0, moved_m = 0;
  bool beyond = false;
};
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
void ApplyPrior(const std::optional<MotionPrior>& prior, RegistrationResult* r) {
  if (!prior || !r->valid) return;
  const PriorDistance d = DistanceFromPrior(*prior, r->T_target_source);
  if (!d.beyond) return;
  r->valid = false;
  r->outside_prior = true;
  char note[200];
  std::snprintf(note, sizeof(note),
                "; not valid: %.1f deg and %.1f cm from the motion prior (tolerance %.1f deg, "
                "%.1f cm)",
                d.turned_deg, d.moved_m * 100, prior->max_rotation_deg,
                prior->max_translation_m * 100);
  r->reason += note;
}

// MotionPrior: no source gave a valid pose within the prior, so ICP starts from the prior itself
// and the check judges where it lands, as for any estimate (refined only when the scans agree at
// least as well after ICP; Refine). There are no correspondences, so nothing anchors ICP but the
// depth: the prior's tolerance bounds how far it may slide. Taken only when valid.
void JudgePriorPose(const Prepared& source, const Prepared& target, const PipelineConfig& config,
                    const MotionPrior& prior, RegistrationResult* result) {
  if (!config.verify.enabled) {
    result->reason +=
        " [motion prior: ICP from it not tried: verify.enabled is false, so nothing "
        "could judge where it lands]";
    return;
  }
  RegistrationResult r;
  r.path = kPriorPath;
  r.T_target_source = prior.T_target_source;
  r.count_test_passed = true;  // the evidence is the prior itself
  r.reason = "started from the motion prior";
  ApplyVerification(source, target, config, "prior", &r);
  if (config.refine.enabled) Refine(source, target, config, &r);
  ApplyPrior(prior, &r);
  // No correspondence pins this pose: where the check finds the geometry degenerate nothing fixes
  // the motion it leaves open (ICP slid a HoloLens wall pair 29 cm from a prior 10 cm off, and the
  // check accepted it; hololens-office 135 <- 51), as for the extra sources
  // (HypothesesConfig::refuse_degenerate). Their brightness test is not applied: it stops the
  // geometry source's global search from lining up two different rooms, which ICP held near the
  // prior does not do, and the truth of hololens-office 124 <- 371 (a table lit differently at
  // its two ends) scores 0.35 on it.
  if (r.valid && r.verification.degenerate) {
    r.valid = false;
    r.reason +=
        "; not valid: the geometry is degenerate and no correspondence fixes the motion "
        "it leaves open";
  }
  if (r.T_target_source != prior.T_target_source) r.path = kPriorIcpPath;
  std::vector<CandidateSummary> candidates = result->candidates;
  candidates.insert(candidates.end(), r.candidates.begin(), r.candidates.end());
  if (r.valid) {
    r.reason +=
        " [no source gave a valid pose within the motion prior; before it: " + result->reason + "]";
    Adopt(std::move(r), result);
  } else {
    result->reason += " [motion prior: ICP from it is not valid either: " + r.reason + "]";
  }
  result->candidates = std::move(candidates);
}

std::atomic<std::uint64_t> g_next_pipeline_id{1};

}  // namespace

bool ComesFromMotionPrior(const RegistrationResult& result) {
  return result.path == kPriorPath || result.path == kPriorIcpPath;
}

struct Pipeline::Impl {
  PipelineConfig config;
  std::uint64_t id = g_next_pipeline_id++;
  std::unique_ptr<FeatureExtractor> extractor;
  std::unique_ptr<DescriptorMatcher> matcher;
  std::unique_ptr<Detector> detector;
  std::unique_ptr<Segmenter> segmenter;
  std::unique_ptr<TextEmbedder> embedder;
  std::unique_ptr<CorrespondenceSource> correspondence_source;

  // Prepare without the input check (the caller made it, naming the scan's role). A scan that
  // will only be a source (Register(scan, scan)) skips what only a target needs (ICP normals).
  std::shared_ptr<const Prepared> PrepareChecked(const Scan& scan, bool as_target = true) const {
    auto p = std::make_shared<Prepared>();
    p->pipeline_id = id;
    p->scan = scan;
    StageTimer perceive_timer, geometry_timer;
    const auto perceive = [&] {
      p->perceived = std::make_shared<const PerceivedScan>(
          correspondence_source->Perceive(scan, perceive_timer));
    };
    // The geometry of the later stages depends on depth alone: it is made while the models look
    // at the images.
    const auto geometry = [&] {
      geometry_timer.Restart();
      if (config.verify.enabled) p->surface = SampleSurface(scan, config.verify);
      if (config.refine.enabled) {
        p->icp = ScanIcpGeometry(scan, IcpSchedule(config.refine), as_target,
                                 config.refine.pixel_stride);
      }
      geometry_timer.Mark("geometry");
    };
    RunBoth(config.threads >= 2, perceive, geometry);
    p->timings = perceive_timer.times();
    for (const StageTime& t : geometry_timer.times()) p->timings.push_back(t);
    p->memory_bytes = PreparedBytes(*p);
    return p;
  }

  const Prepared& Check(const std::shared_ptr<const Prepared>& data,
                        const std::string& role) const {
    if (!data) {
      throw MakeInputError(role + " prepared scan",
                           "is empty; expected the result of Pipeline::Prepare");
    }
    if (data->pipeline_id != id) {
      throw MakeInputError(role + " prepared scan '" + data->scan.name + "'",
                           "was prepared by another Pipeline; expected one prepared by this "
                           "Pipeline (its config decided the features, objects and clouds)");
    }
    return *data;
  }

  // Everything after Prepare: §3.3-3.4 correspondences, RANSAC, verification, ICP.
  RegistrationResult RegisterPrepared(const std::shared_ptr<const Prepared>& source_ptr,
                                      const std::shared_ptr<const Prepared>& target_ptr,
                                      const std::optional<MotionPrior>& prior,
                                      StageTimer& timer) const;
};

Pipeline::Pipeline(const PipelineConfig& config) : impl_(std::make_unique<Impl>()) {
  ValidateConfig(config, "config");
  impl_->config = config;
  ResolveEngine(config.inference);  // inference.engine=onnxruntime without it: fail here, named
  const std::string assets =
      NeedsAssets(config) ? ResolveAssetsDir(config.assets_dir) : config.assets_dir;
  Impl& m = *impl_;
  const auto load_features = [&] {
    m.extractor = MakeFeatureExtractor(config.features, assets, config.inference);
    m.matcher = MakeDescriptorMatcher(config.match);
  };
  if (!config.method.object_level) {
    load_features();
    m.correspondence_source = std::make_unique<ImageCorrespondenceSource>(
        *m.extractor, *m.matcher, config.lift, WholeImageViewPairsOf(config.method),
        config.threads);
    return;
  }
  const auto load_objects = [&] {
    m.detector = MakeDetector(config.detector,
                              ResolveDetectorModels(config.detector, config.inference, assets),
                              config.inference);
    SegmenterConfig segmenter = config.segmenter;
    segmenter.seed = config.seed;  // every random step derives its seed from the pipeline's
    m.segmenter = MakeSegmenter(segmenter, assets, config.inference);
    if (config.method.clip) m.embedder = MakeTextEmbedder(config.semantics, assets);
  };
  // The model files are independent: the feature extractor is verified and loaded on a second
  // thread while the object models load here. Most of it is single-threaded (sha256 of the file,
  // ONNX Runtime's graph optimisation of a session: ~100 ms for XFeat), so the two halves
  // overlap instead of adding up. The models are the same either way; a failure of the features is
  // reported first whatever the thread count (RunBoth).
  RunBoth(config.threads >= 2, load_features, load_objects);
  m.correspondence_source = std::make_unique<ObjectCorrespondenceSource>(
      m.config, *m.extractor, *m.detector, *m.segmenter, m.embedder.get(), *m.matcher);
}

Pipeline::~Pipeline() = default;

const PipelineConfig& Pipeline::config() const { return impl_->config; }

RegistrationResult Pipeline::Impl::RegisterPrepared(
    const std::shared_ptr<const Prepared>& source_ptr,
    const std::shared_ptr<const Prepared>& target_ptr, const std::optional<MotionPrior>& prior,
    StageTimer& timer) const {
  const Prepared& source = *source_ptr;
  const Prepared& target = *target_ptr;
  RegistrationResult result;
  CorrespondenceSet found = correspondence_source->Find(source.perceived, target.perceived, timer);
  result.path = found.path.empty() ? correspondence_source->name() : found.path;
  result.source_objects = source.perceived->object_summaries;
  result.target_objects = target.perceived->object_summaries;
  result.object_matches = std::move(found.object_matches);
  result.rejected_object_matches = found.rejected_object_matches;
  result.num_keypoints_source = source.perceived->num_keypoints;
  result.num_keypoints_target = target.perceived->num_keypoints;
  timer.Restart();
  // Row (b) of Table 4 judges a handful of centroid pairs, each off by up to a few decimetres;
  // every later step (fallback, refinement) uses the same effective thresholds.
  PipelineConfig effective = config;
  if (result.path == "object-centroids") {
    effective.ransac.inlier_threshold_m = config.method.object_centroid_threshold_m;
    effective.ransac.min_inliers = 3;
  }
  HypothesisInputs more;  // issue 12: what the extra hypotheses reuse from the method's run
  if (config.hypotheses.enabled && result.path == "object") {
    more.object_correspondences = found.correspondences;
  }
  std::vector<Correspondence> whole_image_cache;  // matched once, used by fallback and hypotheses
  bool whole_image_matched = false;
  if (found.whole_image_fallback) {
    more.whole_image = [&]() {
      if (!whole_image_matched) whole_image_cache = found.whole_image_fallback();
      whole_image_matched = true;
      return whole_image_cache;
    };
  }
  // (e): the whole-image matching with the source's images turned (hypotheses.turned_images).
  // Every source perceives its views through view_lifts; a scan without them has no features.
  if (extractor && matcher && source.perceived->view_lifts.size() == source.scan.views.size()) {
    more.whole_image_turned = [this, source_ptr, target_ptr]() {
      const Prepared& s = *source_ptr;
      std::call_once(s.turned_once, [&] {
        s.turned = ExtractTurnedFeatures(*extractor, s.scan, s.perceived->view_lifts);
        std::size_t bytes = 0;
        for (const std::vector<LiftedFeatures>& turn : s.turned) {
          for (const LiftedFeatures& f : turn) bytes += LiftedFeaturesBytes(f);
        }
        s.turned_bytes = bytes;
      });
      return MatchTurnedWholeImages(s.turned, s.perceived->view_features,
                                    target_ptr->perceived->view_features, *matcher,
                                    WholeImageViewPairsOf(config.method),
                                    config.hypotheses.turned_min_matches, config.threads);
    };
  }
  Estimate(std::move(found.correspondences), effective, &result);
  timer.Mark("estimate");
  ApplyVerification(source, target, effective, result.path + " ransac", &result);
  ApplyPrior(prior, &result);
  timer.Mark("verify");

  // A correct estimate a few centimetres or degrees off can fail the check and pass after ICP
  // (the fallback's often does). The object level's estimate gets the same chance before the
  // whole images are matched: on redkitchen-gap60 200 -> 260, 270 -> 330 and 570 -> 630 the
  // object RANSAC estimate was 4-8 deg off and refused, and the fallback's refined estimate
  // returned instead, at the same pose ICP reaches from either.
  bool refined = false;
  const bool refine_before_fallback = config.refine.enabled && config.verify.enabled &&
                                      config.refine.before_fallback &&
                                      found.whole_image_fallback != nullptr;
  if (!result.valid && refine_before_fallback && result.count_test_passed) {
    timer.Restart();
    Refine(source, target, effective, &result);
    ApplyPrior(prior, &result);
    timer.Mark("refine");
    refined = true;
    // Only ICP made it pass: the whole-image estimate is its rival (image_rival_rescued).
    more.object_rescued_by_icp = result.valid && result.path == "object";
  }
  // §3.4 found too little inside the matched objects: match the whole images instead (the
  // features are already extracted) and keep whichever estimate is valid.
  if (!result.valid && found.whole_image_fallback) {
    const std::string object_reason = result.reason;
    RegistrationResult fallback = result;
    fallback.correspondences = more.whole_image();
    more.whole_image_tried = true;
    timer.Mark("point_match");
    Estimate(std::move(fallback.correspondences), effective, &fallback);
    timer.Mark("estimate");
    fallback.path = "image-fallback";
    ApplyVerification(source, target, effective, "image-fallback ransac", &fallback);
    ApplyPrior(prior, &fallback);
    timer.Mark("verify");
    fallback.reason += " (object level: " + object_reason + ")";
    // The object estimate was refined: so is the fallback's before the two are compared.
    bool fallback_refined = false;
    if (refined && !fallback.valid && fallback.count_test_passed) {
      timer.Restart();
      Refine(source, target, effective, &fallback);
      ApplyPrior(prior, &fallback);
      timer.Mark("refine");
      fallback_refined = true;
    }
    // Neither passed: the judge is the same check, so the estimate the scans agree with more is
    // returned (still invalid; ICP below may yet make it pass unless both were refined already).
    // Both candidates are listed.
    const bool object_better =
        config.verify.enabled && !fallback.valid && result.count_test_passed &&
        (!fallback.count_test_passed || result.verification.score > fallback.verification.score);
    if (object_better) {
      result.candidates = fallback.candidates;
      result.reason += " (the whole-image fallback scored lower: " + fallback.reason + ")";
    } else {
      result = std::move(fallback);
      refined = fallback_refined;
    }
  }
  // ICP runs whenever there is an estimate the correspondences support (count evidence): a
  // correct estimate a few centimetres off can fail the check and pass after refinement.
  if (config.refine.enabled && result.count_test_passed && !refined) {
    timer.Restart();
    Refine(source, target, effective, &result);
    timer.Mark("refine");
  }
  ApplyPrior(prior, &result);
  // Estimates, checks and refines one source's correspondences; `rule`: what its refinement must
  // keep of the estimate's evidence besides the method's own test (KeptEvidence).
  const auto make_judge = [&](KeptEvidence rule) -> JudgeFn {
    return [&, rule](const std::string& path, std::vector<Correspondence> found_here,
                     const PipelineConfig& e) {
      RegistrationResult r;
      r.path = path;
      Estimate(std::move(found_here), e, &r);
      ApplyVerification(source, target, e, path, &r);
      if (e.refine.enabled && r.count_test_passed) Refine(source, target, e, &r, rule);
      ApplyPrior(prior, &r);
      return r;
    };
  };
  const JudgeFn judge = make_judge({});
  // A valid object-path estimate against the whole-image one (hypotheses.image_rival and its
  // degenerate and rescued forms, which compare the two over the source surface).
  more.source_surface = &source.surface;
  if (JudgeImageRival(config, effective, more, judge, timer, &result)) {
    more.whole_image_tried = true;
  }
  if (WantMoreHypotheses(config, result)) {
    JudgeMoreHypotheses(source.scan, target.scan, config, more,
                        make_judge({/*fraction_always=*/false, /*min_kept=*/4}),
                        make_judge({/*fraction_always=*/true, /*min_kept=*/4}), timer, &result);
  }
  if (prior && !result.valid) {
    timer.Restart();
    JudgePriorPose(source, target, effective, *prior, &result);
    timer.Mark("hypothesis prior");
  }
  for (CandidateSummary& c : result.candidates) {
    c.chosen = c.T_target_source == result.T_target_source;
    c.outside_prior = c.passed && prior && DistanceFromPrior(*prior, c.T_target_source).beyond;
  }
  if (config.object_match.agree_with_result && result.valid) {
    KeepObjectMatchesThatMoveWith(result.T_target_source, found.object_match_points,
                                  config.ransac.inlier_threshold_m, &result);
  }
  return result;
}

PreparedScan Pipeline::Prepare(const Scan& scan, bool as_target) const {
  CheckScan(scan, "prepared");
  PreparedScan out;
  out.data_ = impl_->PrepareChecked(scan, as_target);
  return out;
}

RegistrationResult Pipeline::Register(const PreparedScan& source, const PreparedScan& target,
                                      const std::optional<MotionPrior>& prior) const {
  const auto start = std::chrono::steady_clock::now();
  impl_->Check(source.data_, "source");
  impl_->Check(target.data_, "target");
  CheckPrior(prior);
  StageTimer timer;
  RegistrationResult result = impl_->RegisterPrepared(source.data_, target.data_, prior, timer);
  result.timings = timer.times();
  result.timings.push_back({"total", MillisecondsSince(start)});
  return result;
}

RegistrationResult Pipeline::Register(const Scan& source, const Scan& target,
                                      const std::optional<MotionPrior>& prior) const {
  const auto start = std::chrono::steady_clock::now();
  CheckScan(source, "source");
  CheckScan(target, "target");
  CheckPrior(prior);
  // The two scans' perception is independent: with two threads each scan is prepared on its own
  // (the models serialise their inference, so one scan's detector overlaps the other's features).
  std::shared_ptr<const Prepared> s, t;
  RunBoth(
      impl_->config.threads >= 2, [&] { s = impl_->PrepareChecked(source, /*as_target=*/false); },
      [&] { t = impl_->PrepareChecked(target); });
  StageTimer timer;
  // Per-scan stages first, summed over both scans (when they ran at once they add up to more
  // than the wall time), then the per-pair stages; "total" is the wall time of the call.
  for (const Prepared* p : {s.get(), t.get()}) {
    for (const StageTime& st : p->timings) timer.Add(st.stage, st.ms);
  }
  RegistrationResult result = impl_->RegisterPrepared(s, t, prior, timer);
  result.timings = timer.times();
  result.timings.push_back({"total", MillisecondsSince(start)});
  return result;
}

RegistrationResult Register(const Scan& source, const Scan& target, const PipelineConfig& config,
                            const std::optional<MotionPrior>& prior) {
  return Pipeline(config).Register(source, target, prior);
}

}  // namespace zeroreg
