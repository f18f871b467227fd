// The whole images with the source's turned by the quarter turn (90, 180 or 270 deg) that shares
// the most distinctive matches with the target: XFeat's descriptors are not invariant to the
// camera rolling about its axis. Turned the right way these are the fallback's own
// correspondences, so they are estimated as the fallback's are (ransac.estimator and its inlier
// ratio, which a turn matched by chance does not reach).
#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {
namespace {

class TurnedImagesSource : public PoseSource {
 public:
  std::string name() const override { return "turned images"; }
  CostClass cost() const override { return CostClass::kTurned; }
  unsigned needs() const override { return kNeedsFeatures; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string* note) const override {
    const PipelineConfig& config = pair.config;
    const HypothesesConfig& h = config.hypotheses;
    const Prepared& s = pair.source;
    // Every source perceives its views through view_lifts; a scan without them has no features.
    if (!h.turned_images || pair.extractor == nullptr || pair.matcher == nullptr ||
        s.perceived->view_lifts.size() != s.scan.views.size()) {
      return std::nullopt;
    }
    const FeatureExtractor& extractor = *pair.extractor;
    std::call_once(s.turned_once, [&] {
      s.turned = ExtractTurnedFeatures(extractor, s.scan, s.perceived->view_lifts);
      std::size_t bytes = 0;
      for (const std::vector<LiftedFeatures>& turn : s.turned) {
        for (const LiftedFeatures& f : turn) bytes += LiftedFeaturesBytes(f);
      }
      s.turned_bytes = bytes;
    });
    TurnedWholeImage turned = MatchTurnedWholeImages(
        s.turned, s.perceived->view_features, pair.target.perceived->view_features, *pair.matcher,
        WholeImageViewPairsOf(config.method), h.turned_min_matches, config.threads);
    const std::array<int, 4>& o = turned.overlap_scores;
    *note = "image-turned: distinctive matches at 0/90/180/270 deg " + std::to_string(o[0]) + "/" +
            std::to_string(o[1]) + "/" + std::to_string(o[2]) + "/" + std::to_string(o[3]);
    if (turned.quarter_turns == 0) {
      *note += turned.best_turn > 0
                   ? ", none matched: fewer than " + std::to_string(h.turned_min_matches) +
                         " for the best turn"
                   : ", no turn above the unturned images";
      return std::nullopt;
    }
    Proposal p;
    constexpr PathSource kTurns[] = {PathSource::kImageTurned90, PathSource::kImageTurned180,
                                     PathSource::kImageTurned270};
    p.path = {kTurns[turned.quarter_turns - 1], PathEstimatorOf(config.ransac.estimator)};
    p.correspondences = std::move(turned.correspondences);
    p.effective = config;
    // May be valid in degenerate geometry, where the image correspondences fix the open motion;
    // the refinement is held to the extra sources' floor.
    p.keep = {/*fraction_always=*/false, /*min_kept=*/4};
    return p;
  }
};

}  // namespace

std::unique_ptr<PoseSource> MakeTurnedImagesSource() {
  return std::make_unique<TurnedImagesSource>();
}

}  // namespace zeroreg
