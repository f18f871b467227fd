#include "pipeline/handedness.hpp"

#include <algorithm>
#include <cstdio>

#include <opencv2/core.hpp>

namespace zeroreg {

std::vector<LiftedFeatures> ExtractMirroredFeatures(const FeatureExtractor& extractor,
                                                    const Scan& scan,
                                                    const std::vector<ViewLift>& lifts) {
  std::vector<LiftedFeatures> out;
  for (size_t v = 0; v < scan.views.size() && v < lifts.size(); ++v) {
    const View& view = scan.views[v];
    cv::Mat flipped;
    cv::flip(view.color, flipped, 1);
    const ImageFeatures all = extractor.Extract(flipped);
    std::vector<int> keep;
    LiftedFeatures f;
    for (int i = 0; i < all.size(); ++i) {
      // Flipped pixel x shows the view's pixel w - 1 - x (pixel centres at integers).
      const Eigen::Vector2f pixel(static_cast<float>(view.color.cols - 1) - all.keypoints[i].x(),
                                  all.keypoints[i].y());
      if (auto point = LiftPixel(view, pixel, lifts[v])) {
        keep.push_back(i);
        f.points.push_back(*point);
      }
    }
    f.features = all.Subset(keep);
    for (Eigen::Vector2f& k : f.features.keypoints) {
      k.x() = static_cast<float>(view.color.cols - 1) - k.x();
    }
    out.push_back(std::move(f));
  }
  return out;
}

int DistinctiveMatches(const std::vector<LiftedFeatures>& source,
                       const std::vector<LiftedFeatures>& target) {
  int sum = 0;
  for (const LiftedFeatures& s : source) {
    int best = 0;
    for (const LiftedFeatures& t : target) best = std::max(best, ViewOverlapScore(s, t));
    sum += best;
  }
  return sum;
}

double MirrorThreshold(const Handedness& h, const VerifyConfig& config) {
  return std::max(static_cast<double>(config.mirror_min_matches), config.mirror_ratio * h.as_given);
}

bool LooksMirrored(const Handedness& h, const VerifyConfig& config) {
  return config.mirror_min_matches > 0 && h.mirrored >= MirrorThreshold(h, config);
}

void RefuseMirrorImage(const Prepared& source, const Prepared& target,
                       const FeatureExtractor* extractor, const VerifyConfig& config,
                       RegistrationResult* r) {
  if (!r->valid || !config.enabled || config.mirror_min_matches <= 0 || extractor == nullptr ||
      !source.perceived || !target.perceived ||
      source.perceived->view_lifts.size() != source.scan.views.size()) {
    return;
  }
  Handedness h;
  h.as_given = DistinctiveMatches(source.perceived->view_features, target.perceived->view_features);
  if (h.as_given >= kMirrorTestBelow) return;
  std::call_once(source.mirrored_once, [&] {
    source.mirrored =
        ExtractMirroredFeatures(*extractor, source.scan, source.perceived->view_lifts);
    std::size_t bytes = 0;
    for (const LiftedFeatures& f : source.mirrored) bytes += LiftedFeaturesBytes(f);
    source.turned_bytes += bytes;
  });
  h.mirrored = DistinctiveMatches(source.mirrored, target.perceived->view_features);
  if (!LooksMirrored(h, config)) return;
  r->valid = false;
  r->refusal = {RefusalTest::kMirrorImage, static_cast<double>(h.mirrored),
                MirrorThreshold(h, config)};
  char note[300];
  std::snprintf(note, sizeof(note),
                "; not valid: the source's images match the target's better flipped left-right "
                "(%d distinctive matches flipped, %d as given): a mirror image, which no rigid "
                "motion maps onto the other scan",
                h.mirrored, h.as_given);
  r->reason += note;
}

}  // namespace zeroreg
