// Whole-image correspondences: features over the full image of view i of the source matched with
// view i of the target (the paper pairs views by index), lifted to 3D with depth. This is the
// paper's Table 4 row (a), "w/o Object-Level", and the fallback when objects find too little.
#pragma once

#include "estimate/lift.hpp"
#include "features/feature_extractor.hpp"
#include "pipeline/correspondence_source.hpp"
#include "point_match/descriptor_matcher.hpp"

namespace zeroreg {

// Features of one view restricted to keypoints with usable depth, with their 3D points.
struct LiftedFeatures {
  ImageFeatures features;
  std::vector<Eigen::Vector3d> points;  // scan frame, parallel to features.keypoints
};
LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const LiftConfig& lift);

class ImageCorrespondenceSource : public CorrespondenceSource {
 public:
  ImageCorrespondenceSource(const FeatureExtractor& extractor, const DescriptorMatcher& matcher,
                            const LiftConfig& lift)
      : extractor_(extractor), matcher_(matcher), lift_(lift) {}
  std::string name() const override { return "image"; }
  CorrespondenceSet Find(const Scan& source, const Scan& target, StageTimer& timer) const override;

 private:
  const FeatureExtractor& extractor_;
  const DescriptorMatcher& matcher_;
  LiftConfig lift_;
};

}  // namespace zeroreg
