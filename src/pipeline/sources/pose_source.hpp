// A source proposes a pose for a pair: correspondences for the judge to estimate from, or a pose
// to start from. Each way of proposing (objects §3.4, whole images, turned images, geometry,
// object centroids, the motion prior) is one class behind this interface; the arbiter asks them
// by cost class, cheapest first (arbiter.hpp).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "features/feature_extractor.hpp"
#include "pipeline/judge.hpp"
#include "pipeline/prepared.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "synthesis/virtual_cameras.hpp"

namespace zeroreg {

// When a source is asked, cheapest and best-founded first. A later class runs only while no
// earlier one gave a decisive candidate (the arbiter's rule).
enum class CostClass {
  kMethod = 0,      // the method's own correspondences (§3.3-3.4), already matched
  kWholeImage = 1,  // the same features matched over the whole images (one matching)
  kExtra = 2,       // other estimators and features: clique on the same matches, FPFH, centroids
  kTurned = 3,      // three more feature extractions per view (cached per scan), one matching
  kSynthesis = 4,   // the target rendered into a few virtual cameras, features of each rendering
  kPrior = 5,       // ICP from the caller's motion prior: no correspondence pins it
  // Asked only by the ambiguity test, for a second pose away from a valid one (PairInputs::first):
  // turns of it, then ICP.
  kSecondPose = 6,
};

// What a source reads of the pair (its `needs` says which parts).
enum Need : unsigned {
  kNeedsFeatures = 1u << 0,  // the views' features (extractor, matcher)
  kNeedsObjects = 1u << 1,   // the method's objects and their matches
  kNeedsDepth = 1u << 2,     // the scans' depth alone
  kNeedsPrior = 1u << 3,     // a MotionPrior
};

// The whole-image correspondences, matched once per pair however many sources ask.
class WholeImageMatches {
 public:
  explicit WholeImageMatches(std::function<std::vector<Correspondence>()> match)
      : match_(std::move(match)) {}
  bool available() const { return match_ != nullptr; }
  const std::vector<Correspondence>& Get() {
    if (!done_) found_ = match_();
    done_ = true;
    return found_;
  }
  // They were already estimated with ransac.estimator (the fallback or the rival).
  bool tried_with_method_estimator = false;

 private:
  std::function<std::vector<Correspondence>()> match_;
  bool done_ = false;
  std::vector<Correspondence> found_;
};

struct PairInputs {
  const Prepared& source;
  const Prepared& target;
  const PipelineConfig& config;
  const std::optional<MotionPrior>& prior;
  const FeatureExtractor* extractor = nullptr;  // null: no features (the turned images need them)
  const DescriptorMatcher* matcher = nullptr;
  // The method's correspondences inside matched objects (§3.4); empty off the object path.
  std::vector<Correspondence> object_correspondences;
  WholeImageMatches* whole_image = nullptr;          // null or unavailable: no fallback features
  const RegistrationResult* method = nullptr;        // the method's objects and object matches
  const PipelineConfig* method_effective = nullptr;  // the method's thresholds (Table 4 row b)
  // kSecondPose: the valid result a second pose is sought away from.
  const RegistrationResult* first = nullptr;
  // Every candidate checked so far (the arbiter's log): pose hypotheses to render from.
  const std::vector<CandidateSummary>* candidates = nullptr;
};

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  virtual std::string name() const = 0;
  virtual CostClass cost() const = 0;
  virtual unsigned needs() const = 0;  // Need bits
  // The proposal for this pair, or nothing (disabled, or too little to estimate from). `note`
  // receives what the source measured when it matters for the reason (may stay empty).
  virtual std::optional<Proposal> Propose(PairInputs& pair, std::string* note) const = 0;
};

// The extra sources of the given cost class, in the order they are asked (kExtra: object
// correspondences with the low-inlier estimator, whole images, geometry, centroids; kTurned: the
// turned images).
std::vector<std::unique_ptr<PoseSource>> MakeSources(CostClass cost);

// The path estimator named by an estimator's name ("ransac" or "clique", the two ValidateConfig
// admits).
PathEstimator PathEstimatorOf(const std::string& estimator);

// The extra sources' estimator and count test (HypothesesConfig documents why).
PipelineConfig ExtraSourceConfig(const PipelineConfig& config);

// FPFH correspondences between the two scans' geometry (exposed for tests).
std::vector<Correspondence> GeometryCorrespondences(const Scan& source, const Scan& target,
                                                    const PipelineConfig& config);

// One centroid correspondence per same-label object pair, plus every matched pair.
std::vector<Correspondence> ObjectPairCorrespondences(const RegistrationResult& result);

// The source view's features matched against the target rendered into `camera` (view synthesis),
// with the RANSAC inliers of one motion among them (exposed for tests).
struct SynthesizedMatches {
  std::vector<Correspondence> correspondences;  // target pixels in the rendering, target_view -1
  double covered = 0;                           // fraction of the rendering with surface
  int rendered_keypoints = 0;                   // usable keypoints of the rendering
  int inliers = 0;
  Transform T_target_source = Transform::Identity();
  VirtualCamera camera;
};
// Only cameras whose rendering covers at least `min_covered` of the image are matched.
SynthesizedMatches MatchRenderedView(const Scan& target, const VirtualCamera& camera,
                                     const Intrinsics& K, const LiftedFeatures& source_features,
                                     const FeatureExtractor& extractor,
                                     const DescriptorMatcher& matcher, const PipelineConfig& config,
                                     double min_covered);

// ICP from the caller's motion prior (path "prior", "prior icp" once ICP moved it).
std::unique_ptr<PoseSource> MakePriorSource();

}  // namespace zeroreg
