#include "features/feature_extractor.hpp"

#include "features/sift_extractor.hpp"
#include "features/xfeat_extractor.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {

ImageFeatures ImageFeatures::Subset(const std::vector<int>& keep) const {
  ImageFeatures out;
  out.keypoints.reserve(keep.size());
  out.scores.reserve(keep.size());
  out.descriptors.resize(static_cast<Eigen::Index>(keep.size()), descriptors.cols());
  for (size_t r = 0; r < keep.size(); ++r) {
    const int i = keep[r];
    out.keypoints.push_back(keypoints[i]);
    out.scores.push_back(scores[i]);
    out.descriptors.row(static_cast<Eigen::Index>(r)) = descriptors.row(i);
  }
  return out;
}

std::unique_ptr<FeatureExtractor> MakeFeatureExtractor(const FeatureConfig& config,
                                                       const std::string& assets_dir,
                                                       const InferenceConfig& inference) {
  if (config.backend == "xfeat") {
    const std::string model = RequireAsset(assets_dir, XFeatExtractor::ModelFile(inference));
    return std::make_unique<XFeatExtractor>(model, config, inference);
  }
  if (config.backend == "sift") return std::make_unique<SiftExtractor>(config);
  throw MakeInputError("features.backend", "unknown feature backend '" + config.backend +
                                               "'; expected \"xfeat\" or \"sift\"");
}

}  // namespace zeroreg
