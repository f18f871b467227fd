// The object level's correspondences (§3.4) again, estimated by hypotheses.estimator (the
// clique estimator by default) where it differs from the method's: at wide baselines a few right
// matches among many wrong ones are below what RANSAC samples reliably.
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {
namespace {

class ObjectCliqueSource : public PoseSource {
 public:
  std::string name() const override { return "object"; }
  CostClass cost() const override { return CostClass::kExtra; }
  unsigned needs() const override { return kNeedsObjects | kNeedsFeatures; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string*) const override {
    const HypothesesConfig& h = pair.config.hypotheses;
    if (pair.object_correspondences.empty() || h.estimator == pair.config.ransac.estimator) {
      return std::nullopt;
    }
    Proposal p;
    p.path = {PathSource::kObject, PathEstimatorOf(h.estimator)};
    p.correspondences = pair.object_correspondences;
    p.effective = ExtraSourceConfig(pair.config);
    p.keep = {/*fraction_always=*/false, /*min_kept=*/4};
    p.refuse_degenerate = h.refuse_degenerate;
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakeObjectCliqueSource() {
  return std::make_unique<ObjectCliqueSource>();
}

}  // namespace zeroreg
