// Object centroids: every same-label object pair of the two scans as one correspondence (not
// only the matched pairs, so a swapped match of two chairs still leaves the right pairs in),
// judged at the centroid distance of the paper's Table 4 row (b).
#include <set>
#include <utility>

#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {

std::vector<Correspondence> ObjectPairCorrespondences(const RegistrationResult& result) {
  std::set<std::pair<int, int>> pairs;
  for (size_t i = 0; i < result.source_objects.size(); ++i) {
    for (size_t j = 0; j < result.target_objects.size(); ++j) {
      if (result.source_objects[i].label == result.target_objects[j].label) {
        pairs.emplace(static_cast<int>(i), static_cast<int>(j));
      }
    }
  }
  for (const ObjectMatchSummary& m : result.object_matches) pairs.emplace(m.source, m.target);
  std::vector<Correspondence> out;
  for (const auto& [i, j] : pairs) {
    Correspondence c;
    c.source = result.source_objects[static_cast<size_t>(i)].centroid;
    c.target = result.target_objects[static_cast<size_t>(j)].centroid;
    c.score = 1.0f;
    c.view = -1;
    c.target_view = -1;
    out.push_back(c);
  }
  return out;
}

namespace {

class CentroidSource : public PoseSource {
 public:
  std::string name() const override { return "object-pairs"; }
  CostClass cost() const override { return CostClass::kExtra; }
  unsigned needs() const override { return kNeedsObjects; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string*) const override {
    const PipelineConfig& config = pair.config;
    const HypothesesConfig& h = config.hypotheses;
    if (!h.objects || pair.method == nullptr) return std::nullopt;
    std::vector<Correspondence> pairs = ObjectPairCorrespondences(*pair.method);
    if (pairs.size() < 3) return std::nullopt;
    Proposal p;
    p.path = {PathSource::kObjectPairs, PathEstimatorOf(h.estimator)};
    p.correspondences = std::move(pairs);
    p.effective = ExtraSourceConfig(config);
    p.effective.ransac.inlier_threshold_m = config.method.object_centroid_threshold_m;
    p.effective.ransac.min_inliers = 3;
    // A few centroids pin no surface: ICP from their estimate keeps its evidence always.
    p.keep = {/*fraction_always=*/true, /*min_kept=*/4};
    p.refuse_degenerate = h.refuse_degenerate;
    p.images_must_agree = true;
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakeCentroidSource() { return std::make_unique<CentroidSource>(); }

}  // namespace zeroreg
