#include "pipeline/image_source.hpp"

namespace zeroreg {

PerceivedScan ImageCorrespondenceSource::Perceive(const Scan& scan, StageTimer& timer) const {
  PerceivedScan out;
  timer.Restart();
  for (const View& view : scan.views) {
    out.view_lifts.push_back(LiftForView(lift_, depth_, view));
    out.view_features.push_back(ExtractLiftedFeatures(extractor_, view, out.view_lifts.back()));
  }
  out.num_keypoints = CountKeypoints(out.view_features);
  timer.Mark("features");
  return out;
}

CorrespondenceSet ImageCorrespondenceSource::Find(
    const std::shared_ptr<const PerceivedScan>& source,
    const std::shared_ptr<const PerceivedScan>& target, StageTimer& timer) const {
  CorrespondenceSet result;
  timer.Restart();
  MatchWholeImages(source->view_features, target->view_features, matcher_, view_pairs_, threads_,
                   &result.correspondences);
  timer.Mark("match");
  return result;
}

}  // namespace zeroreg
