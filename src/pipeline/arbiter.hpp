// The arbiter: asks the sources (sources/pose_source.hpp) cheapest first, has each proposal judged
// (judge.hpp), stops by one rule, picks the winner and says why (Arbiter::Decide).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "pipeline/judge.hpp"
#include "pipeline/sources/pose_source.hpp"
#include "pipeline/stage_timer.hpp"

namespace zeroreg {

// Turns a proposal into a judged candidate (Judge::Full; tests stand in for it).
// With a timer, the judge marks its stages.
using JudgeFn = std::function<Judged(Proposal, StageTimer*)>;

// Ranking of two judged candidates: validity first, then count evidence, then the check's score.
bool Better(const RegistrationResult& a, const RegistrationResult& b);

// Whether the extra cost classes are asked for this result: hypotheses.enabled, verification on,
// and the result not valid unless hypotheses.always.
bool WantMoreSources(const PipelineConfig& config, const RegistrationResult& result);

// Why a valid object-path candidate is not decisive, so the whole images are asked against it.
struct Doubt {
  bool degenerate = false;  // the check found the geometry degenerate (image_rival_degenerate)
  bool rescued = false;     // it passed only after ICP (image_rival_rescued)
  bool single = false;      // it rests on one object match (image_rival_single)
  bool any(const PipelineConfig& config) const {
    return config.hypotheses.image_rival || degenerate || rescued || single;
  }
};
Doubt DoubtOf(const PipelineConfig& config, const Judged& held);

// Which rule lets the whole-image rival replace the held object-path candidate; kNone: it stays.
enum class RivalWin { kNone, kScore, kSupport, kRescuedScore, kSingleScore };
struct RivalMeasure {
  double apart_m = 0;          // EstimateDisplacementRms of the two
  double apart_surface_m = 0;  // PointDisplacementRms over the source surface
};
RivalWin RivalRule(const PipelineConfig& config, const Doubt& doubt, const RegistrationResult& held,
                   const RegistrationResult& rival, const RivalMeasure& measure);

// Whether a valid result's evidence settles it without the ambiguity test: enough image
// correspondences support it (ambiguity.decisive_inliers) from a source that matched images.
bool Decisive(const PipelineConfig& config, const RegistrationResult& result);

// Whether `second` rivals the valid `first` (the ambiguity rule): the check can tell them apart
// (`apart_m`, their RMS distance over the source surface, beyond ICP's widest gate
// refine.max_distance_coarse_m: closer, ICP from one reaches the other and they are one answer),
// it lies at least 45 deg from first (half the smallest turn a second pose starts from: closer,
// ICP went back toward first), no motion prior rules it out, it passed the check judged with
// ambiguity.max_violation, its images agree where its depth does
// (hypotheses.min_brightness_rank_correlation) and its score is at least
// ambiguity.min_score_fraction of first's.
bool Rivals(const PipelineConfig& config, const RegistrationResult& first,
            const RegistrationResult& second, double apart_m);

class Arbiter {
 public:
  Arbiter(JudgeFn judge, PairInputs& pair, StageTimer& timer)
      : judge_(std::move(judge)), pair_(pair), timer_(timer) {}
  // `method`: the method's proposal (§3.4, or its whole-image flow); `scans`: what belongs to the
  // scans (objects, their matches, keypoint counts), kept in the result whatever wins.
  RegistrationResult Decide(Proposal method, RegistrationResult scans);

 private:
  Judged Ask(Proposal p, bool timed = false);
  // `winner` replaces *held, keeping what belongs to the scans (Adopt).
  static void Replace(Judged winner, Judged* held);
  void Instead(Judged* held);  // the whole images instead of a method candidate that failed
  // The whole images against a valid one that is not decisive, for the reasons in `doubt`.
  void Against(const Doubt& doubt, Judged* held);
  void MoreSources(Judged* held);
  void FromPrior(Judged* held);
  // The ambiguity test: second poses away from a valid one that is not decisive.
  void SecondPose(Judged* held);

  JudgeFn judge_;
  PairInputs& pair_;
  StageTimer& timer_;
  std::vector<CandidateSummary> log_;  // every candidate checked, in order
};

}  // namespace zeroreg
