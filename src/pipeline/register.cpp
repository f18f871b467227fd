#include "zeroreg/register.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "estimate/icp.hpp"
#include "estimate/lift.hpp"
#include "estimate/max_clique.hpp"
#include "estimate/rigid_ransac.hpp"
#include "eval/metrics.hpp"
#include "features/feature_extractor.hpp"
#include "pipeline/hypotheses.hpp"
#include "pipeline/image_correspondences.hpp"
#include "pipeline/object_correspondences.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "verify/verify.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg {
namespace {

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
void ApplyVerification(const Scan& source, const Scan& target, const PipelineConfig& config,
                       const std::string& name, RegistrationResult* r) {
  if (!config.verify.enabled) return;
  const bool evidence = r->count_test_passed;
  r->verification = VerifyRegistration(source, target, r->T_target_source, config.verify);
  r->candidates.push_back(
      {name, r->T_target_source, r->verification.score, evidence && r->verification.passed, false});
  if (!evidence) return;  // the count reason stands
  r->valid = r->verification.passed;
  r->reason = r->verification.reason + " (" + r->reason + ")";
}

// Coarse-to-fine point-to-plane ICP from the estimate. The refined transform is kept only when
// the geometric check scores it at least as well as the estimate it started from (issue 10) and
// at least half of the estimate's inlier correspondences stay within its coarse gate: ICP fits all
// of both scans' geometry, so where it slides (along a plane, pulled by surface one scan sees
// alone) the scans agree less or the image evidence is left behind, and the estimate stays. Without
// verification ICP is kept.
void Refine(const Scan& source, const Scan& target, const PipelineConfig& pipeline,
            RegistrationResult* r) {
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
  // Every other depth pixel is plenty: the stages thin the points to 2 cm voxels or coarser.
  const IcpResult icp =
      RefinePointToPlane(ScanPoints(source, /*stride=*/2), ScanPoints(target, /*stride=*/2),
                         r->T_target_source, stages, anchors);
  const double moved_m = TranslationErrorM(icp.T_target_source, r->T_target_source);
  const double turned_deg = RotationErrorDeg(icp.T_target_source, r->T_target_source);
  RegistrationResult refined = *r;
  refined.T_target_source = icp.T_target_source;
  UpdateInlierStats(pipeline.ransac.inlier_threshold_m, &refined);
  char note[320];
  if (pipeline.verify.enabled) {
    refined.verification =
        VerifyRegistration(source, target, refined.T_target_source, pipeline.verify);
    refined.candidates.push_back({r->path + " icp", refined.T_target_source,
                                  refined.verification.score, refined.verification.passed, false});
    r->candidates = refined.candidates;
    // A refinement keeps the evidence it started from: most of the correspondences that
    // supported the estimate stay within ICP's own pull-in range (the coarse gate) of the refined
    // transform. ICP that left them (moved 25-70 cm into another minimum of the depth fit, measured
    // on cabinet-gap3 and hololens-gap5) is a new registration the image evidence contradicts, not
    // a refinement. (Counting them at the 5 cm inlier distance instead rejected correct 5 cm
    // corrections on redkitchen-gap60: RANSAC's inliers sit up to 5 cm off its own estimate.)
    const int kept = CountWithin(*r, icp.T_target_source, config.max_distance_coarse_m);
    if (kept < config.min_kept_inlier_fraction * r->num_inliers) {
      std::snprintf(note, sizeof(note),
                    "; ICP refinement rejected: only %d of the %d correspondences that support "
                    "the estimate stay within %.2f m of it (it would move %.1f cm, %.2f deg)",
                    kept, r->num_inliers, config.max_distance_coarse_m, moved_m * 100, turned_deg);
      r->reason += note;
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
DetectorModelPaths ResolveDetectorModels(const DetectorConfig& config, const std::string& assets) {
  DetectorModelPaths paths;
  if (config.backend == "yolox") {
    paths.yolox_onnx = RequireAsset(assets, "yolox_nano_coco/yolox_nano.onnx");
    paths.yolox_classes = RequireAsset(assets, "yolox_nano_coco/coco_classes.txt");
  } else if (config.backend == "darknet") {
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
  return c.detector.backend != "file" || c.method.clip;
}

}  // namespace

struct Pipeline::Impl {
  PipelineConfig config;
  std::unique_ptr<FeatureExtractor> extractor;
  std::unique_ptr<DescriptorMatcher> matcher;
  std::unique_ptr<Detector> detector;
  std::unique_ptr<Segmenter> segmenter;
  std::unique_ptr<TextEmbedder> embedder;
  std::unique_ptr<CorrespondenceSource> source;
};

Pipeline::Pipeline(const PipelineConfig& config) : impl_(std::make_unique<Impl>()) {
  ValidateConfig(config, "config");
  impl_->config = config;
  const std::string assets =
      NeedsAssets(config) ? ResolveAssetsDir(config.assets_dir) : config.assets_dir;
  Impl& m = *impl_;
  m.extractor = MakeFeatureExtractor(config.features, assets);
  m.matcher = MakeDescriptorMatcher(config.match);
  if (!config.method.object_level) {
    m.source = std::make_unique<ImageCorrespondenceSource>(
        *m.extractor, *m.matcher, config.lift, config.method.whole_image_all_view_pairs);
    return;
  }
  m.detector = MakeDetector(config.detector, ResolveDetectorModels(config.detector, assets));
  SegmenterConfig segmenter = config.segmenter;
  segmenter.seed = config.seed;  // every random step derives its seed from the pipeline's
  m.segmenter = MakeSegmenter(segmenter);
  if (config.method.clip) m.embedder = MakeTextEmbedder(config.semantics, assets);
  m.source = std::make_unique<ObjectCorrespondenceSource>(
      m.config, *m.extractor, *m.detector, *m.segmenter, m.embedder.get(), *m.matcher);
}

Pipeline::~Pipeline() = default;

const PipelineConfig& Pipeline::config() const { return impl_->config; }

RegistrationResult Pipeline::Register(const Scan& source, const Scan& target) const {
  CheckScan(source, "source");
  CheckScan(target, "target");
  const PipelineConfig& config = impl_->config;
  StageTimer timer;
  RegistrationResult result;
  CorrespondenceSet found = impl_->source->Find(source, target, timer);
  result.path = found.path.empty() ? impl_->source->name() : found.path;
  result.source_objects = std::move(found.source_objects);
  result.target_objects = std::move(found.target_objects);
  result.object_matches = std::move(found.object_matches);
  result.num_keypoints_source = found.num_keypoints_source;
  result.num_keypoints_target = found.num_keypoints_target;
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
  Estimate(std::move(found.correspondences), effective, &result);
  timer.Mark("estimate");
  ApplyVerification(source, target, effective, result.path + " ransac", &result);
  timer.Mark("verify");

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
    timer.Mark("verify");
    fallback.reason += " (object level: " + object_reason + ")";
    // Neither passed: the judge is the same check, so the estimate the scans agree with more is
    // returned (still invalid; ICP below may yet make it pass). Both candidates are listed.
    const bool object_better =
        config.verify.enabled && !fallback.valid && result.count_test_passed &&
        (!fallback.count_test_passed || result.verification.score > fallback.verification.score);
    if (object_better) {
      result.candidates = fallback.candidates;
      result.reason += " (the whole-image fallback scored lower: " + fallback.reason + ")";
    } else {
      result = std::move(fallback);
    }
  }
  // ICP runs whenever there is an estimate the correspondences support (count evidence): a
  // correct estimate a few centimetres off can fail the check and pass after refinement.
  if (config.refine.enabled && result.count_test_passed) {
    timer.Restart();
    Refine(source, target, effective, &result);
    timer.Mark("refine");
  }
  if (WantMoreHypotheses(config, result)) {
    const JudgeFn judge = [&](const std::string& path, std::vector<Correspondence> found_here,
                              const PipelineConfig& e) {
      RegistrationResult r;
      r.path = path;
      Estimate(std::move(found_here), e, &r);
      ApplyVerification(source, target, e, path, &r);
      if (e.refine.enabled && r.count_test_passed) Refine(source, target, e, &r);
      return r;
    };
    JudgeMoreHypotheses(source, target, config, more, judge, timer, &result);
  }
  for (CandidateSummary& c : result.candidates) {
    c.chosen = c.T_target_source == result.T_target_source;
  }
  double total = 0;
  for (const StageTime& t : timer.times()) total += t.ms;
  result.timings = timer.times();
  result.timings.push_back({"total", total});
  return result;
}

RegistrationResult Register(const Scan& source, const Scan& target, const PipelineConfig& config) {
  return Pipeline(config).Register(source, target);
}

}  // namespace zeroreg
