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

CorrespondenceSet ImageCorrespondenceSource::Find(const Scan& source, const Scan& target,
                                                  StageTimer& timer) const {
  CorrespondenceSet result;
  const size_t view_pairs = std::min(source.views.size(), target.views.size());
  for (size_t v = 0; v < view_pairs; ++v) {
    timer.Restart();
    const LiftedFeatures s = ExtractLiftedFeatures(extractor_, source.views[v], lift_);
    const LiftedFeatures t = ExtractLiftedFeatures(extractor_, target.views[v], lift_);
    timer.Mark("features");
    result.num_keypoints_source += s.features.size();
    result.num_keypoints_target += t.features.size();
    for (const DescriptorMatch& m :
         matcher_.Match(s.features.descriptors, t.features.descriptors)) {
      Correspondence c;
      c.source = s.points[m.source];
      c.target = t.points[m.target];
      c.source_pixel = s.features.keypoints[m.source];
      c.target_pixel = t.features.keypoints[m.target];
      c.view = static_cast<int>(v);
      c.target_view = static_cast<int>(v);
      c.score = m.score;
      result.correspondences.push_back(c);
    }
    timer.Mark("match");
  }
  return result;
}

}  // namespace zeroreg
