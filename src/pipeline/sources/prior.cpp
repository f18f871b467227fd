// The caller's motion prior as a source: ICP starts from it and the check judges where it lands,
// as for any estimate. No correspondence pins this pose, so where the check finds the geometry
// degenerate nothing fixes the motion it leaves open (a wall pair slid 29 cm from a prior 10 cm
// off), and such a candidate is refused. The images' brightness test is not asked: it stops a
// global search from lining up two rooms, which ICP held near the prior does not do.
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {
namespace {

class PriorSource : public PoseSource {
 public:
  std::string name() const override { return "prior"; }
  CostClass cost() const override { return CostClass::kPrior; }
  unsigned needs() const override { return kNeedsPrior | kNeedsDepth; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string* note) const override {
    if (!pair.prior) return std::nullopt;
    if (!pair.config.verify.enabled) {
      *note =
          "motion prior: ICP from it not tried: verify.enabled is false, so nothing could judge "
          "where it lands";
      return std::nullopt;
    }
    Proposal p;
    p.path = {PathSource::kPrior};
    p.pose = pair.prior->T_target_source;
    p.effective = pair.method_effective != nullptr ? *pair.method_effective : pair.config;
    p.refuse_degenerate = true;
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakePriorSource() { return std::make_unique<PriorSource>(); }

bool ComesFromMotionPrior(const RegistrationResult& result) {
  return result.path.source == PathSource::kPrior;
}

}  // namespace zeroreg
