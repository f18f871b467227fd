// The scans' own geometry: FPFH on the depth clouds, mutual nearest neighbours in feature space.
// No image took part, so the images must agree where the depth does.
#include <algorithm>

#include "estimate/lift.hpp"
#include "features/fpfh.hpp"
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {

std::vector<Correspondence> GeometryCorrespondences(const Scan& source, const Scan& target,
                                                    const PipelineConfig& config) {
  const HypothesesConfig& h = config.hypotheses;
  FpfhParams params;
  params.voxel_m = h.geometry_voxel_m;
  const FpfhCloud s = ComputeFpfh(ScanPoints(source, PixelGrid{h.geometry_pixel_stride},
                                             config.depth.min_m, config.depth.max_m),
                                  params);
  const FpfhCloud t = ComputeFpfh(ScanPoints(target, PixelGrid{h.geometry_pixel_stride},
                                             config.depth.min_m, config.depth.max_m),
                                  params);
  std::vector<Correspondence> out;
  for (const FeaturePair& m : MutualFeatureMatches(s, t, config.threads)) {
    Correspondence c;
    c.source = s.points[static_cast<size_t>(m.source)];
    c.target = t.points[static_cast<size_t>(m.target)];
    c.score = m.score;
    c.view = -1;  // not from an image
    c.target_view = -1;
    out.push_back(c);
  }
  return out;
}

namespace {

class GeometrySource : public PoseSource {
 public:
  std::string name() const override { return "geometry"; }
  CostClass cost() const override { return CostClass::kExtra; }
  unsigned needs() const override { return kNeedsDepth; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string*) const override {
    const PipelineConfig& config = pair.config;
    const HypothesesConfig& h = config.hypotheses;
    if (!h.geometry) return std::nullopt;
    Proposal p;
    p.path = {PathSource::kGeometry, PathEstimatorOf(h.estimator)};
    p.correspondences = GeometryCorrespondences(pair.source.scan, pair.target.scan, config);
    p.effective = ExtraSourceConfig(config);
    // Correspondences between voxel centres are off by up to about a voxel even when right, so
    // their inlier distance is 1.5 voxels (as the FPFH baseline's, --method fpfh).
    p.effective.ransac.inlier_threshold_m =
        std::max(config.ransac.inlier_threshold_m, 1.5 * h.geometry_voxel_m);
    p.keep = {/*fraction_always=*/false, /*min_kept=*/4};
    p.refuse_degenerate = h.refuse_degenerate;
    p.images_must_agree = true;
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakeGeometrySource() { return std::make_unique<GeometrySource>(); }

}  // namespace zeroreg
