// The whole-image correspondence source (paper Table 4 row (a), "w/o Object-Level"): every view's
// features over the full image, matched as MatchWholeImages does.
#pragma once

#include "pipeline/correspondence_source.hpp"
#include "pipeline/image_correspondences.hpp"

namespace zeroreg {

class ImageCorrespondenceSource : public CorrespondenceSource {
 public:
  ImageCorrespondenceSource(const FeatureExtractor& extractor, const DescriptorMatcher& matcher,
                            const LiftConfig& lift, const DepthModel& depth,
                            const WholeImageViewPairs& view_pairs, int threads)
      : extractor_(extractor),
        matcher_(matcher),
        lift_(lift),
        depth_(depth),
        view_pairs_(view_pairs),
        threads_(threads) {}
  PathSource path() const override { return PathSource::kImage; }
  PerceivedScan Perceive(const Scan& scan, StageTimer& timer) const override;
  CorrespondenceSet Find(const std::shared_ptr<const PerceivedScan>& source,
                         const std::shared_ptr<const PerceivedScan>& target,
                         StageTimer& timer) const override;

 private:
  const FeatureExtractor& extractor_;
  const DescriptorMatcher& matcher_;
  LiftConfig lift_;
  DepthModel depth_;
  WholeImageViewPairs view_pairs_;
  int threads_;  // PipelineConfig::threads
};

}  // namespace zeroreg
