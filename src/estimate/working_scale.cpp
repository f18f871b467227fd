#include "estimate/working_scale.hpp"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <vector>

#include "estimate/depth_noise.hpp"
#include "estimate/lift.hpp"

namespace zeroreg {

std::optional<double> WorkingDistance(const Scan& scan) {
  std::vector<float> depths;
  for (const View& view : scan.views) {
    const cv::Mat& depth = view.depth;
    if (depth.empty() || depth.type() != CV_32FC1) continue;
    const int stride = PixelGrid{}.StrideFor(depth.cols);
    for (int y = stride / 2; y < depth.rows; y += stride) {
      const float* row = depth.ptr<float>(y);
      for (int x = stride / 2; x < depth.cols; x += stride) {
        if (row[x] > 0 && std::isfinite(row[x])) depths.push_back(row[x]);
      }
    }
  }
  if (depths.empty()) return std::nullopt;
  const auto middle = depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2);
  std::nth_element(depths.begin(), middle, depths.end());
  return static_cast<double>(*middle);
}

namespace {

// The nearest quarter octave 2^(n/4) to a ratio; exactly 1 within an eighth octave of it.
double QuarterOctave(double ratio) {
  const double quarters = std::round(4.0 * std::log2(ratio));
  return quarters == 0 ? 1.0 : std::exp2(quarters / 4.0);
}

}  // namespace

ScaleEvidence MeasureScale(const Scan& scan) {
  return {WorkingDistance(scan), MeasureDepthNoiseAt1m(scan)};
}

ScaleEvidence PairScale(const ScaleEvidence& source, const ScaleEvidence& target) {
  return {PairWorkingDistance(source.distance_m, target.distance_m),
          PairWorkingDistance(source.noise_at_1m_m, target.noise_at_1m_m)};
}

bool ScaleFromNoise(const ScaleEvidence& evidence, const ScaleConfig& config) {
  const std::optional<double>& d = evidence.distance_m;
  const std::optional<double>& a = evidence.noise_at_1m_m;
  if (!config.automatic || config.working_distance_m > 0 ||
      !(config.structured_light_noise_min_at_1m_m > 0) || !d || !a || !(*d > 0) || !(*a > 0)) {
    return false;
  }
  // Relative noise a d is scale-free: a copy s times the size has s d and a / s.
  const double relative = *a * *d;
  return relative >= config.structured_light_noise_min_at_1m_m * config.structured_light_min_m &&
         relative <= config.structured_light_noise_max_at_1m_m * config.structured_light_max_m;
}

double WorkingScale(const ScaleEvidence& evidence, const ScaleConfig& config) {
  if (ScaleFromNoise(evidence, config)) {
    return QuarterOctave(std::sqrt(config.structured_light_noise_min_at_1m_m *
                                   config.structured_light_noise_max_at_1m_m) /
                         *evidence.noise_at_1m_m);
  }
  return WorkingScale(evidence.distance_m, config);
}

double WorkingScale(std::optional<double> distance_m, const ScaleConfig& config) {
  if (!config.automatic) return 1.0;
  if (config.working_distance_m > 0) distance_m = config.working_distance_m;
  if (!distance_m || !(*distance_m > 0)) return 1.0;
  double ratio = 1.0;
  if (*distance_m < config.room_min_m) ratio = *distance_m / config.room_min_m;
  if (*distance_m > config.room_max_m) ratio = *distance_m / config.room_max_m;
  // Quarter octaves. Just outside the range the ratio rounds to 1.
  return QuarterOctave(ratio);
}

std::optional<double> PairWorkingDistance(std::optional<double> source_m,
                                          std::optional<double> target_m) {
  if (source_m && target_m) return std::sqrt(*source_m * *target_m);
  return source_m ? source_m : target_m;
}

Scan InWorkingUnits(const Scan& scan, double k) {
  Scan out = scan;
  if (k == 1.0) return out;
  const double inverse = 1.0 / k;
  for (View& view : out.views) {
    view.depth = view.depth.clone();
    view.depth *= inverse;  // 0 (invalid) stays 0
    view.T_scan_camera.topRightCorner<3, 1>() *= inverse;
    if (view.T_world_camera_gt) view.T_world_camera_gt->topRightCorner<3, 1>() *= inverse;
  }
  for (Eigen::Vector3d& p : out.points) p *= inverse;
  if (out.T_world_scan_gt) out.T_world_scan_gt->topRightCorner<3, 1>() *= inverse;
  return out;
}

// The result of a registration made in working units of k metres (src/estimate/working_scale.hpp)
// in metres: every transform's translation and every length multiplied by k. The reason's
// prose keeps the working units and says so.
void ResultInMetres(double k, const std::optional<MotionPrior>& prior, RegistrationResult* r) {
  if (k == 1.0) return;
  r->T_target_source.topRightCorner<3, 1>() *= k;
  for (CandidateSummary& c : r->candidates) c.T_target_source.topRightCorner<3, 1>() *= k;
  for (Correspondence& c : r->correspondences) {
    c.source *= k;
    c.target *= k;
  }
  for (auto* objects : {&r->source_objects, &r->target_objects}) {
    for (ObjectSummary& o : *objects) {
      o.centroid *= k;
      for (Eigen::Vector3d& p : o.points) p *= k;
    }
  }
  for (Alternative& a : r->alternatives) {
    a.T_target_source.topRightCorner<3, 1>() *= k;
    a.apart_m *= k;
  }
  if (r->rendered_view) r->rendered_view->T_target_camera.topRightCorner<3, 1>() *= k;
  r->inlier_rmse *= k;
  r->inlier_spread_m *= k;
  r->verification.residual_rms_m *= k;
  switch (r->refusal.test) {
    case RefusalTest::kInliersOnALine:
    case RefusalTest::kAnotherPosePasses:
    case RefusalTest::kAmbiguous:
      r->refusal.measured *= k;
      r->refusal.threshold *= k;
      break;
    case RefusalTest::kOutsidePrior:
      // Metres when the rotation was within the prior (the threshold is then the working prior's
      // translation tolerance); degrees are the same at any scale.
      if (prior && r->refusal.threshold != prior->max_rotation_deg &&
          r->refusal.threshold == prior->max_translation_m / k) {
        r->refusal.measured *= k;
        r->refusal.threshold = prior->max_translation_m;
      }
      break;
    default:
      break;
  }
  char note[160];
  std::snprintf(note, sizeof(note),
                " [working scale %.3g: the lengths above are in units of %.3g m]", k, k);
  r->reason += note;
}

// The prior in working units of k metres.
std::optional<MotionPrior> PriorInWorkingUnits(const std::optional<MotionPrior>& prior, double k) {
  if (!prior || k == 1.0) return prior;
  MotionPrior p = *prior;
  p.T_target_source.topRightCorner<3, 1>() /= k;
  p.max_translation_m /= k;
  return p;
}

}  // namespace zeroreg
