#include "pipeline/image_correspondences.hpp"

#include <algorithm>

namespace zeroreg {

LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const LiftConfig& lift) {
  const ImageFeatures all = extractor.Extract(view.color);
  // Keypoints without usable depth cannot give a 3D correspondence; dropping them before matching
  // also keeps them from stealing a mutual nearest neighbour from a usable keypoint.
  std::vector<int> keep;
  LiftedFeatures out;
  for (int i = 0; i < all.size(); ++i) {
    if (auto point = LiftPixel(view, all.keypoints[i], lift)) {
      keep.push_back(i);
      out.points.push_back(*point);
    }
  }
  out.features = all.Subset(keep);
  return out;
}

int CountKeypoints(const std::vector<LiftedFeatures>& views) {
  int n = 0;
  for (const LiftedFeatures& f : views) n += f.features.size();
  return n;
}

void MatchWholeImages(const std::vector<LiftedFeatures>& source,
                      const std::vector<LiftedFeatures>& target, const DescriptorMatcher& matcher,
                      bool all_view_pairs, std::vector<Correspondence>* out) {
  for (size_t vs = 0; vs < source.size(); ++vs) {
    for (size_t vt = 0; vt < target.size(); ++vt) {
      if (!all_view_pairs && vs != vt) continue;
      const LiftedFeatures& a = source[vs];
      const LiftedFeatures& b = target[vt];
      for (const DescriptorMatch& m :
           matcher.Match(a.features.descriptors, b.features.descriptors)) {
        out->push_back({a.points[m.source], b.points[m.target], a.features.keypoints[m.source],
                        b.features.keypoints[m.target], static_cast<int>(vs), static_cast<int>(vt),
                        m.score});
      }
    }
  }
}

}  // namespace zeroreg
