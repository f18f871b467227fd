// View synthesis: the target scan rendered (src/synthesis/render.hpp) into virtual cameras near
// where the source camera may be, its features extracted from the renderings and matched against
// the source's image. Image features stop matching beyond about 40-50 deg of viewpoint change,
// which is what revisits from across a room are made of; rendered from a pose 20-30 deg off, the
// target shows its surface from nearly the source's side and the change left to the matcher is
// what remains of the guess. Every rendered pixel carries the target's 3D point, so the matches
// are 3D-3D correspondences as the whole images' are, estimated and judged the same way.
//
// Virtual cameras: the source camera as every candidate checked so far places it (the arbiter's
// log, valid or not), near-duplicates merged; with none, the target's cameras swung about the
// vertical through the surface they see (OrbitCameras). The camera whose matches most agree on
// one motion (RANSAC inliers) is kept, and rendered once more from that motion's estimate when
// it lies elsewhere; the better of the two is proposed.
#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "estimate/max_clique.hpp"
#include "pipeline/sources/pose_source.hpp"
#include "synthesis/render.hpp"
#include "synthesis/virtual_cameras.hpp"

namespace zeroreg {

SynthesizedMatches MatchRenderedView(const Scan& target, const VirtualCamera& camera,
                                     const Intrinsics& K, const LiftedFeatures& source_features,
                                     const FeatureExtractor& extractor,
                                     const DescriptorMatcher& matcher, const PipelineConfig& config,
                                     double min_covered) {
  SynthesizedMatches out;
  out.camera = camera;
  RenderConfig render;
  render.depth = config.depth;
  const RenderedView view = RenderScan(target, camera.T_target_camera, K, render);
  out.covered = static_cast<double>(view.covered) / std::max(1, K.width * K.height);
  if (out.covered < min_covered) return out;
  // Keypoints on the border of a hole describe an edge the renderer made, not the surface: only
  // those with every pixel within kHoleMarginPx covered are kept.
  constexpr int kHoleMarginPx = 3;
  cv::Mat covered = view.depth > 0, inside;
  cv::erode(covered, inside,
            cv::getStructuringElement(cv::MORPH_RECT,
                                      cv::Size(2 * kHoleMarginPx + 1, 2 * kHoleMarginPx + 1)));
  const ImageFeatures all = extractor.Extract(view.color);
  std::vector<int> keep;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < all.size(); ++i) {
    const int u = static_cast<int>(std::lround(all.keypoints[i].x()));
    const int v = static_cast<int>(std::lround(all.keypoints[i].y()));
    if (u < 0 || v < 0 || u >= inside.cols || v >= inside.rows || !inside.at<uchar>(v, u)) continue;
    const cv::Vec3f p = view.points.at<cv::Vec3f>(v, u);
    keep.push_back(i);
    points.emplace_back(p[0], p[1], p[2]);
  }
  const ImageFeatures rendered = all.Subset(keep);
  out.rendered_keypoints = rendered.size();
  if (rendered.size() < 3 || source_features.features.size() < 3) return out;
  for (const DescriptorMatch& m :
       matcher.Match(source_features.features.descriptors, rendered.descriptors, config.threads)) {
    out.correspondences.push_back({source_features.points[m.source], points[m.target],
                                   source_features.features.keypoints[m.source],
                                   rendered.keypoints[m.target], camera.source_view,
                                   /*target_view=*/-1, m.score});
  }
  if (out.correspondences.size() < 3) return out;
  std::vector<Eigen::Vector3d> src, tgt;
  std::vector<float> scores;
  for (const Correspondence& c : out.correspondences) {
    src.push_back(c.source);
    tgt.push_back(c.target);
    scores.push_back(c.score);
  }
  const RansacResult fit = EstimateRigid(src, tgt, scores, config.ransac, config.seed);
  out.inliers = fit.num_inliers;
  out.T_target_source = fit.T_target_source;
  return out;
}

namespace {

// Candidates of the arbiter's log worth rendering from, in the order they were checked.
std::vector<PoseHypothesis> Hypotheses(const PairInputs& pair) {
  std::vector<PoseHypothesis> out;
  if (pair.candidates == nullptr) return out;
  for (const CandidateSummary& c : *pair.candidates) {
    if (!c.T_target_source.allFinite()) continue;
    out.push_back({c.name, c.T_target_source});
  }
  return out;
}

std::string Describe(const SynthesizedMatches& m) {
  char line[200];
  std::snprintf(line, sizeof(line), "%s (%.0f%% covered, %d matches, %d agree)",
                m.camera.from.c_str(), 100.0 * m.covered,
                static_cast<int>(m.correspondences.size()), m.inliers);
  return line;
}

class ViewSynthesisSource : public PoseSource {
 public:
  std::string name() const override { return "view synthesis"; }
  CostClass cost() const override { return CostClass::kSynthesis; }
  unsigned needs() const override { return kNeedsFeatures | kNeedsDepth; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string* note) const override {
    const PipelineConfig& config = pair.config;
    const HypothesesConfig& h = config.hypotheses;
    const Prepared& s = pair.source;
    const Scan& target = pair.target.scan;
    if (!h.view_synthesis || pair.extractor == nullptr || pair.matcher == nullptr ||
        s.perceived->view_features.size() != s.scan.views.size()) {
      return std::nullopt;
    }
    // A camera where a target view's own camera is renders that view's image again, which the
    // whole images already matched.
    const auto at_target_camera = [&](const Transform& T) {
      for (const View& v : target.views) {
        if (NearCamera(T, v.T_scan_camera, kMergeDeg, kMergeM)) return true;
      }
      return false;
    };
    std::vector<VirtualCamera> cameras;
    for (const VirtualCamera& c :
         CamerasFromHypotheses(Hypotheses(pair), s.scan, kMergeDeg, kMergeM, /*max_cameras=*/0)) {
      if (static_cast<int>(cameras.size()) >= h.synthesis_max_cameras) break;
      if (!at_target_camera(c.T_target_camera)) cameras.push_back(c);
    }
    if (cameras.empty() || h.synthesis_orbits) {
      for (VirtualCamera& c : OrbitCameras(target, {-60, -30, 30, 60}, /*source_view=*/0)) {
        cameras.push_back(std::move(c));
      }
    }

    const auto match = [&](const VirtualCamera& camera) {
      const auto v = static_cast<size_t>(camera.source_view);
      return MatchRenderedView(target, camera, s.scan.views[v].intrinsics,
                               s.perceived->view_features[v], *pair.extractor, *pair.matcher,
                               config, h.synthesis_min_covered);
    };
    SynthesizedMatches best;
    std::string tried;
    for (const VirtualCamera& camera : cameras) {
      SynthesizedMatches m = match(camera);
      tried += (tried.empty() ? "" : ", ") + Describe(m);
      if (m.inliers > best.inliers) best = std::move(m);
    }
    *note = "view-synthesis: " + std::to_string(cameras.size()) + " cameras: " + tried;
    if (best.inliers < kMinAgreeing) {
      *note += "; none with " + std::to_string(kMinAgreeing) + " matches agreeing on one motion";
      return std::nullopt;
    }
    // Once more from where the best matches put the source camera, when that is elsewhere: the
    // closer the rendering's viewpoint, the more of the source's features find their match.
    const auto v = static_cast<size_t>(best.camera.source_view);
    const Transform again = best.T_target_source * s.scan.views[v].T_scan_camera;
    if (!NearCamera(again, best.camera.T_target_camera, kIterateDeg, kIterateM)) {
      SynthesizedMatches m =
          match({"iterated from " + best.camera.from, best.camera.source_view, again});
      *note += "; " + Describe(m);
      if (m.inliers > best.inliers) best = std::move(m);
    }
    Proposal p;
    p.path = {PathSource::kViewSynthesis, PathEstimatorOf(config.ransac.estimator)};
    p.correspondences = std::move(best.correspondences);
    p.rendered_view = RenderedCamera{best.camera.source_view, best.camera.T_target_camera,
                                     s.scan.views[v].intrinsics, best.camera.from};
    // Image correspondences as the whole images' (the fallback's estimator and count test).
    p.effective = config;
    p.keep = {/*fraction_always=*/false, /*min_kept=*/4};
    p.refuse_degenerate = h.refuse_degenerate;
    return p;
  }

 private:
  // Cameras this close render nearly the same image (and the matcher tolerates far more).
  static constexpr double kMergeDeg = 10.0, kMergeM = 0.25;
  // The estimate is rendered again only when it moved the camera at least this much.
  static constexpr double kIterateDeg = 3.0, kIterateM = 0.1;
  // Three matches fit some rigid motion whenever their distances agree.
  static constexpr int kMinAgreeing = 4;
};

}  // namespace

std::unique_ptr<PoseSource> MakeViewSynthesisSource() {
  return std::make_unique<ViewSynthesisSource>();
}

}  // namespace zeroreg
