// The whole images' correspondences (paper Table 4 row (a)) estimated by hypotheses.estimator,
// unless the method's fallback or rival already estimated them the same way.
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {
namespace {

class WholeImageSource : public PoseSource {
 public:
  std::string name() const override { return "image"; }
  CostClass cost() const override { return CostClass::kExtra; }
  unsigned needs() const override { return kNeedsFeatures; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string*) const override {
    const HypothesesConfig& h = pair.config.hypotheses;
    if (!h.image || pair.whole_image == nullptr || !pair.whole_image->available()) {
      return std::nullopt;
    }
    if (pair.whole_image->tried_with_method_estimator &&
        h.estimator == pair.config.ransac.estimator) {
      return std::nullopt;
    }
    Proposal p;
    p.path = {PathSource::kImage, PathEstimatorOf(h.estimator)};
    p.correspondences = pair.whole_image->Get();
    p.effective = ExtraSourceConfig(pair.config);
    p.keep = {/*fraction_always=*/false, /*min_kept=*/4};
    p.refuse_degenerate = h.refuse_degenerate;
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakeWholeImageSource() { return std::make_unique<WholeImageSource>(); }

}  // namespace zeroreg
