#include "zeroreg/register.hpp"

#include <cstdio>
#include <sstream>

#include "estimate/icp.hpp"
#include "estimate/rigid_ransac.hpp"
#include "eval/metrics.hpp"
#include "features/feature_extractor.hpp"
#include "pipeline/image_correspondences.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

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
  std::ostringstream why;
  if (r->num_correspondences < 3) {
    why << "only " << r->num_correspondences
        << " 3D correspondences; at least 3 are needed to estimate a rigid transform";
  } else if (r->num_inliers < config.min_inliers) {
    why << "only " << r->num_inliers << " RANSAC inliers of " << r->num_correspondences
        << " correspondences (need at least " << config.min_inliers << ")";
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

// Point-to-plane ICP from the RANSAC estimate; kept only if it stays a refinement.
void Refine(const Scan& source, const Scan& target, const RefineConfig& config,
            RegistrationResult* r) {
  const IcpResult icp =
      RefinePointToPlane(ScanGeometry(source, config.voxel_m), ScanGeometry(target, config.voxel_m),
                         r->T_target_source, config);
  const double moved_m = TranslationErrorM(icp.T_target_source, r->T_target_source);
  const double turned_deg = RotationErrorDeg(icp.T_target_source, r->T_target_source);
  char note[160];
  if (moved_m <= config.max_translation_change_m && turned_deg <= config.max_rotation_change_deg) {
    r->T_target_source = icp.T_target_source;
    std::snprintf(note, sizeof(note), "; refined by ICP (fitness %.2f, moved %.1f cm, %.2f deg)",
                  icp.fitness, moved_m * 100, turned_deg);
  } else {
    std::snprintf(note, sizeof(note), "; ICP refinement rejected (would move %.1f cm, %.2f deg)",
                  moved_m * 100, turned_deg);
  }
  r->reason += note;
}

}  // namespace

struct Pipeline::Impl {
  PipelineConfig config;
  std::unique_ptr<FeatureExtractor> extractor;
  std::unique_ptr<DescriptorMatcher> matcher;
  std::unique_ptr<CorrespondenceSource> source;
};

Pipeline::Pipeline(const PipelineConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  const std::string assets = config.features.backend == "sift"
                                 ? config.assets_dir  // SIFT needs no model file
                                 : ResolveAssetsDir(config.assets_dir);
  impl_->extractor = MakeFeatureExtractor(config.features, assets);
  impl_->matcher = MakeDescriptorMatcher(config.match);
  impl_->source =
      std::make_unique<ImageCorrespondenceSource>(*impl_->extractor, *impl_->matcher, config.lift);
}

Pipeline::~Pipeline() = default;

const PipelineConfig& Pipeline::config() const { return impl_->config; }

RegistrationResult Pipeline::Register(const Scan& source, const Scan& target) const {
  CheckScan(source, "source");
  CheckScan(target, "target");
  StageTimer timer;
  RegistrationResult result;
  result.path = impl_->source->name();

  CorrespondenceSet found = impl_->source->Find(source, target, timer);
  result.num_keypoints_source = found.num_keypoints_source;
  result.num_keypoints_target = found.num_keypoints_target;
  result.correspondences = std::move(found.correspondences);
  result.num_correspondences = static_cast<int>(result.correspondences.size());

  timer.Restart();
  std::vector<Eigen::Vector3d> src, tgt;
  src.reserve(result.correspondences.size());
  tgt.reserve(result.correspondences.size());
  for (const Correspondence& c : result.correspondences) {
    src.push_back(c.source);
    tgt.push_back(c.target);
  }
  const RansacResult ransac =
      EstimateRigidRansac(src, tgt, impl_->config.ransac, impl_->config.seed);
  timer.Mark("estimate");
  result.T_target_source = ransac.T_target_source;
  result.is_inlier = ransac.is_inlier;
  result.num_inliers = ransac.num_inliers;
  result.inlier_rmse = ransac.inlier_rmse;
  result.ransac_iterations = ransac.iterations;
  result.inlier_ratio = result.num_correspondences > 0
                            ? static_cast<double>(ransac.num_inliers) / result.num_correspondences
                            : 0.0;
  DecideVerdict(impl_->config.ransac, &result);
  if (impl_->config.refine.enabled && result.valid) {
    timer.Restart();
    Refine(source, target, impl_->config.refine, &result);
    timer.Mark("refine");
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
