// Which sources exist, by cost class. A new source is a new file and one line here.
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {

std::unique_ptr<PoseSource> MakeObjectCliqueSource();
std::unique_ptr<PoseSource> MakeWholeImageSource();
std::unique_ptr<PoseSource> MakeGeometrySource();
std::unique_ptr<PoseSource> MakeCentroidSource();
std::unique_ptr<PoseSource> MakeTurnedImagesSource();
std::vector<std::unique_ptr<PoseSource>> MakeTurnedPoseSources();
std::unique_ptr<PoseSource> MakeViewSynthesisSource();

std::vector<std::unique_ptr<PoseSource>> MakeSources(CostClass cost) {
  std::vector<std::unique_ptr<PoseSource>> out;
  if (cost == CostClass::kExtra) {
    out.push_back(MakeObjectCliqueSource());
    out.push_back(MakeWholeImageSource());
    out.push_back(MakeGeometrySource());
    out.push_back(MakeCentroidSource());
  } else if (cost == CostClass::kTurned) {
    out.push_back(MakeTurnedImagesSource());
  } else if (cost == CostClass::kSynthesis) {
    out.push_back(MakeViewSynthesisSource());
  } else if (cost == CostClass::kPrior) {
    out.push_back(MakePriorSource());
  } else if (cost == CostClass::kSecondPose) {
    out = MakeTurnedPoseSources();
  }
  return out;
}

PathEstimator PathEstimatorOf(const std::string& estimator) {
  return estimator == "clique" ? PathEstimator::kClique : PathEstimator::kRansac;
}

PipelineConfig ExtraSourceConfig(const PipelineConfig& config) {
  PipelineConfig e = config;
  e.ransac.estimator = config.hypotheses.estimator;
  e.ransac.min_inlier_ratio = config.hypotheses.min_inlier_ratio;
  return e;
}

}  // namespace zeroreg
