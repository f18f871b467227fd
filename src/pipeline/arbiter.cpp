#include "pipeline/arbiter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "eval/metrics.hpp"

namespace zeroreg {

bool Better(const RegistrationResult& a, const RegistrationResult& b) {
  if (a.valid != b.valid) return a.valid;
  if (a.count_test_passed != b.count_test_passed) return a.count_test_passed;
  return a.verification.score > b.verification.score;
}

bool WantMoreSources(const PipelineConfig& config, const RegistrationResult& result) {
  return config.hypotheses.enabled && config.verify.enabled &&
         (config.hypotheses.always || !result.valid);
}

Doubt DoubtOf(const PipelineConfig& config, const Judged& held) {
  const HypothesesConfig& h = config.hypotheses;
  Doubt d;
  d.degenerate = h.enabled && h.image_rival_degenerate && held.result.verification.degenerate;
  d.rescued = h.enabled && h.image_rival_rescued && held.result.valid && !held.valid_before_icp;
  d.single = h.enabled && h.image_rival_single && held.result.object_matches.size() == 1;
  return d;
}

RivalWin RivalRule(const PipelineConfig& config, const Doubt& doubt, const RegistrationResult& held,
                   const RegistrationResult& rival, const RivalMeasure& m) {
  if (!rival.valid) return RivalWin::kNone;
  // Two valid estimates farther apart than ICP's widest gate contradict each other: the one the
  // scans agree with more wins (hypotheses.image_rival).
  if (config.hypotheses.image_rival && Disagree(m.apart_m, config) &&
      rival.verification.score > held.verification.score) {
    return RivalWin::kScore;
  }
  // Closer than ICP's final gate over the source surface they are the same answer.
  const bool distinct = m.apart_surface_m > config.refine.max_distance_final_m;
  // Degenerate geometry: the check cannot see the open motion, the correspondences fix it, and
  // the estimate more of them support wins.
  if (doubt.degenerate && distinct && rival.num_inliers > held.num_inliers) {
    return RivalWin::kSupport;
  }
  // Rescued by ICP, or resting on one object match: nothing but the check speaks for the
  // estimate, and the check picks where the two differ (not in degenerate geometry, where its
  // score cannot tell them apart).
  if ((doubt.rescued || doubt.single) && !held.verification.degenerate && distinct &&
      rival.verification.score > held.verification.score) {
    return doubt.rescued ? RivalWin::kRescuedScore : RivalWin::kSingleScore;
  }
  return RivalWin::kNone;
}

namespace {

// Sources whose correspondences come from the images (the method's objects, the whole and the
// turned images); the geometry (FPFH) and the object centroids match shapes, which a symmetric
// scene repeats.
bool RestsOnImages(const Path& path) {
  switch (path.source) {
    case PathSource::kObject:
    case PathSource::kImage:
    case PathSource::kImageFallback:
    case PathSource::kImageRival:
    case PathSource::kImageTurned90:
    case PathSource::kImageTurned180:
    case PathSource::kImageTurned270:
      return true;
    default:
      return false;
  }
}

Alternative AlternativeOf(const RegistrationResult& r, double apart_m) {
  const VerificationResult& v = r.verification;
  return {PathName(r.path), r.T_target_source, v.score,
          v.overlap,        v.violation,       v.brightness_rank_correlation,
          r.num_inliers,    apart_m,           r.outside_prior};
}

}  // namespace

bool Decisive(const PipelineConfig& config, const RegistrationResult& result) {
  return (RestsOnImages(result.path) && result.num_inliers >= config.ambiguity.decisive_inliers) ||
         ComesFromMotionPrior(result);
}

bool Rivals(const PipelineConfig& config, const RegistrationResult& first,
            const RegistrationResult& second, double apart_m) {
  const VerificationResult& v = second.verification;
  const double rho = v.brightness_rank_correlation;
  // The second poses start a quarter turn or more from the first; one that ICP brought back
  // within half of that went back toward the first: the first, badly converged under the relaxed
  // check, not a pose the scene's symmetry allows.
  const double turned_deg = RotationErrorDeg(second.T_target_source, first.T_target_source);
  return apart_m > config.refine.max_distance_coarse_m && turned_deg >= 45.0 &&
         !second.outside_prior && v.passed && std::isfinite(rho) &&
         rho >= config.hypotheses.min_brightness_rank_correlation &&
         v.score >= config.ambiguity.min_score_fraction * first.verification.score;
}

Judged Arbiter::Ask(Proposal p, bool timed) {
  Judged j = judge_(std::move(p), timed ? &timer_ : nullptr);
  log_.insert(log_.end(), j.result.candidates.begin(), j.result.candidates.end());
  return j;
}

// The rule. Sources are asked by cost class, cheapest first, and a class is asked only while no
// earlier one gave a decisive candidate:
//  1. kMethod: the method's correspondences (§3.3-3.4: Eq. 2's object matches, Eq. 3-4's point
//     matches; Table 4 rows a/b in the ablations), judged in full (estimate, count test, check,
//     ICP kept only where the check prefers it, prior).
//  2. kWholeImage: if that candidate is not valid, the whole images instead (same estimator);
//     the one valid, else the better supported by counts and check score, is held. If it is valid
//     but not decisive (an object-path candidate that is degenerate, passed only after ICP, or
//     rests on one object match), the whole images are judged against it and replace it only by
//     RivalRule (the check decides where the two differ; by inliers where it is blind).
//  3. kExtra, then kTurned: while nothing valid is held (or always with hypotheses.always), every
//     source of the class is judged and the best by Better wins; a valid held candidate is never
//     replaced by one farther than ICP's widest gate from it (the check cannot choose between two
//     poses it accepts). kTurned is asked only when kExtra left nothing valid.
//  4. kSecondPose: a valid winner that is not Decisive is judged against turns of itself; one that
//     Rivals it (fits too, farther apart than ICP's widest gate) makes it ambiguous, not valid.
//  5. kPrior: with a motion prior and nothing valid (nor ambiguous), ICP from the prior, taken only
//     when valid.
// An invalid candidate never replaces a held one except in step 2's fallback, where the method's
// candidate stays only if it has count evidence and a higher score while the fallback never
// passed.
RegistrationResult Arbiter::Decide(Proposal method, RegistrationResult scans) {
  const PipelineConfig& config = pair_.config;
  timer_.Restart();
  Judged held = Ask(std::move(method), /*timed=*/true);
  Adopt(std::move(held.result), &scans);
  held.result = std::move(scans);
  const bool whole_image = pair_.whole_image != nullptr && pair_.whole_image->available();
  if (!held.result.valid && whole_image) {
    Instead(&held);
  } else if (held.result.valid && held.result.path == Path{PathSource::kObject} && whole_image &&
             config.verify.enabled) {
    const Doubt doubt = DoubtOf(config, held);
    if (doubt.any(config)) Against(doubt, &held);
  }
  if (WantMoreSources(config, held.result)) MoreSources(&held);
  if (config.ambiguity.enabled && config.verify.enabled && held.result.valid &&
      !Decisive(config, held.result)) {
    SecondPose(&held);
  }
  if (pair_.prior && !held.result.valid && !held.result.ambiguous) FromPrior(&held);
  RegistrationResult result = std::move(held.result);
  result.candidates = std::move(log_);
  for (CandidateSummary& c : result.candidates) {
    c.chosen = c.T_target_source == result.T_target_source;
    c.outside_prior =
        c.passed && pair_.prior && DistanceFromPrior(*pair_.prior, c.T_target_source).beyond;
  }
  return result;
}

void Arbiter::Replace(Judged winner, Judged* held) {
  Adopt(std::move(winner.result), &held->result);
  held->refusal = std::move(winner.refusal);
  held->valid_before_icp = winner.valid_before_icp;
}

void Arbiter::Instead(Judged* held) {
  Proposal p;
  p.path = {PathSource::kImageFallback};
  p.check_name = "image-fallback ransac";
  p.correspondences = pair_.whole_image->Get();
  p.effective = *pair_.method_effective;
  pair_.whole_image->tried_with_method_estimator = true;
  timer_.Mark("point_match");
  Judged fallback = Ask(std::move(p), /*timed=*/true);
  fallback.result.reason += " (object level: " + held->result.reason + ")";
  const RegistrationResult& m = held->result;
  const RegistrationResult& f = fallback.result;
  const bool fallback_passed = f.valid || fallback.valid_before_icp;
  const bool method_better = pair_.config.verify.enabled && !fallback_passed &&
                             m.count_test_passed &&
                             (!f.count_test_passed || m.verification.score > f.verification.score);
  if (method_better) {
    held->result.reason += " (the whole-image fallback scored lower: " + f.reason + ")";
  } else {
    Replace(std::move(fallback), held);
  }
}

void Arbiter::Against(const Doubt& doubt, Judged* held) {
  const PipelineConfig& config = pair_.config;
  RegistrationResult& result = held->result;
  timer_.Restart();
  Proposal p;
  p.path = {PathSource::kImageRival};
  p.correspondences = pair_.whole_image->Get();
  p.effective = *pair_.method_effective;
  Judged judged = Ask(std::move(p));
  pair_.whole_image->tried_with_method_estimator = true;
  timer_.Mark("hypothesis image-rival");
  RegistrationResult& rival = judged.result;
  RivalMeasure m;
  m.apart_m = EstimateDisplacementRms(result, rival);
  m.apart_surface_m =
      PointDisplacementRms(&pair_.source.surface, result.T_target_source, rival.T_target_source);
  const RivalWin win = RivalRule(config, doubt, result, rival, m);
  char line[240];
  std::snprintf(line, sizeof(line), "image-rival: %s, score %.3f, %.3f m RMS from %s",
                rival.valid ? "valid" : "not valid", rival.verification.score, m.apart_m,
                PathName(result.path).c_str());
  char held_summary[120];
  std::snprintf(held_summary, sizeof(held_summary), "%s: score %.3f", PathName(result.path).c_str(),
                result.verification.score);
  char support[200];
  std::snprintf(support, sizeof(support),
                "; inliers %d (%s) against %d (image-rival), %.3f m RMS apart over the source "
                "surface",
                result.num_inliers, PathName(result.path).c_str(), rival.num_inliers,
                m.apart_surface_m);
  const bool asked = doubt.degenerate || doubt.rescued || doubt.single;
  std::string shown_support = asked && win != RivalWin::kScore ? support : "";
  const char* why = nullptr;
  switch (win) {
    case RivalWin::kScore:
      why = "the object path's estimate disagreed with the whole-image one and scored lower";
      break;
    case RivalWin::kSupport:
      why = "degenerate geometry: the whole-image estimate is supported by more correspondences";
      break;
    case RivalWin::kRescuedScore:
      why =
          "the object path's estimate passed the check only after ICP, and the whole-image "
          "estimate scores higher";
      break;
    case RivalWin::kSingleScore:
      why =
          "the object path's estimate rests on one object match, and the whole-image estimate "
          "scores higher";
      break;
    case RivalWin::kNone:
      break;
  }
  if (why != nullptr) {
    rival.reason += std::string(" [") + why + ": " + held_summary + "; " + line + shown_support +
                    "; chosen: image-rival]";
    Replace(std::move(judged), held);
  } else {
    result.reason +=
        std::string(" [checked against the whole-image estimate: ") + line + shown_support + "]";
  }
}

void Arbiter::MoreSources(Judged* held) {
  const PipelineConfig& config = pair_.config;
  RegistrationResult* result = &held->result;
  std::vector<Judged> tried;
  std::string notes;
  const auto ask_class = [&](CostClass cost) {
    for (const std::unique_ptr<PoseSource>& source : MakeSources(cost)) {
      timer_.Restart();
      std::string note;
      std::optional<Proposal> p = source->Propose(pair_, &note);
      if (!note.empty()) notes += "; " + note;
      if (!p && note.empty()) continue;
      if (p) tried.push_back(Ask(std::move(*p)));
      timer_.Mark("hypothesis " + source->name());
    }
  };
  ask_class(CostClass::kExtra);
  const bool any_valid =
      result->valid ||
      std::any_of(tried.begin(), tried.end(), [](const Judged& j) { return j.result.valid; });
  if (!any_valid) ask_class(CostClass::kTurned);
  // The renderings start from every pose checked so far, valid or not.
  pair_.candidates = &log_;
  const bool any_valid_now =
      result->valid ||
      std::any_of(tried.begin(), tried.end(), [](const Judged& j) { return j.result.valid; });
  if (!any_valid_now) ask_class(CostClass::kSynthesis);

  const bool held_valid = result->valid;
  int best = -1, disagreeing = 0;
  for (size_t k = 0; k < tried.size(); ++k) {
    const RegistrationResult& incumbent =
        best < 0 ? *result : tried[static_cast<size_t>(best)].result;
    if (!tried[k].result.valid || !Better(tried[k].result, incumbent)) continue;
    if (held_valid && Disagree(EstimateDisplacementRms(tried[k].result, *result), config)) {
      ++disagreeing;
      continue;
    }
    best = static_cast<int>(k);
  }
  // `refusal`: why a source refused it; otherwise a result the check passed that is not valid
  // is one whose refinement is another accepted pose (Judge::Refine).
  const auto describe = [](const RegistrationResult& r, const std::string& refusal) {
    const char* verdict = r.valid                ? "valid"
                          : !r.count_test_passed ? "no consensus"
                          : !refusal.empty()     ? refusal.c_str()
                          : r.outside_prior      ? "outside the motion prior"
                          : r.verification.passed
                              ? "not valid: another pose passes the check as well"
                              : "refused by the check";
    char line[200];
    std::snprintf(line, sizeof(line), "%s: %s, score %.3f", PathName(r.path).c_str(), verdict,
                  r.verification.score);
    return std::string(line);
  };
  std::string summary = describe(*result, "");
  for (const Judged& j : tried) summary += "; " + describe(j.result, j.refusal);
  summary += notes;
  if (best >= 0) {
    Adopt(std::move(tried[static_cast<size_t>(best)].result), result);
  }
  if (disagreeing > 0) {
    summary += "; " + std::to_string(disagreeing) +
               " valid, higher-scoring, disagreeing with the method's valid estimate: not taken";
  }
  result->reason += " [hypotheses: " + summary + "; chosen: " + PathName(result->path) + "]";
}

void Arbiter::FromPrior(Judged* held) {
  RegistrationResult* result = &held->result;
  timer_.Restart();
  std::string note;
  std::optional<Proposal> p = MakePriorSource()->Propose(pair_, &note);
  if (!p) {
    if (!note.empty()) result->reason += " [" + note + "]";
    return;
  }
  Judged j = Ask(std::move(*p));
  timer_.Mark("hypothesis prior");
  if (j.result.valid) {
    j.result.reason +=
        " [no source gave a valid pose within the motion prior; before it: " + result->reason + "]";
    Adopt(std::move(j.result), result);
  } else {
    result->reason += " [motion prior: ICP from it is not valid either: " + j.result.reason + "]";
  }
}

void Arbiter::SecondPose(Judged* held) {
  RegistrationResult& first = held->result;
  const PipelineConfig& config = pair_.config;
  PairInputs pair = pair_;
  pair.first = &first;
  std::vector<Alternative> rivals, ruled_out;
  timer_.Restart();
  for (const std::unique_ptr<PoseSource>& source : MakeSources(CostClass::kSecondPose)) {
    std::string note;
    std::optional<Proposal> p = source->Propose(pair, &note);
    if (!p) continue;
    const Judged second = Ask(std::move(*p));
    const double apart_m = PointDisplacementRms(&pair_.source.surface, first.T_target_source,
                                                second.result.T_target_source);
    // Within ICP's widest gate of a pose already listed: the same second pose again.
    bool seen = false;
    for (const std::vector<Alternative>* list : {&rivals, &ruled_out}) {
      for (const Alternative& r : *list) {
        seen = seen || PointDisplacementRms(&pair_.source.surface, r.T_target_source,
                                            second.result.T_target_source) <=
                           config.refine.max_distance_coarse_m;
      }
    }
    if (seen) continue;
    if (Rivals(config, first, second.result, apart_m)) {
      rivals.push_back(AlternativeOf(second.result, apart_m));
      break;  // one rival settles it: the result is ambiguous
    } else if (second.result.outside_prior && second.result.verification.passed &&
               apart_m > config.refine.max_distance_coarse_m) {
      RegistrationResult unprioritised = second.result;
      unprioritised.outside_prior = false;
      if (Rivals(config, first, unprioritised, apart_m)) {
        ruled_out.push_back(AlternativeOf(second.result, apart_m));
      }
    }
  }
  timer_.Mark("ambiguity");
  if (rivals.empty() && ruled_out.empty()) return;
  first.alternatives = {AlternativeOf(first, 0.0)};
  for (const std::vector<Alternative>* list : {&rivals, &ruled_out}) {
    first.alternatives.insert(first.alternatives.end(), list->begin(), list->end());
  }
  if (rivals.empty()) {
    first.reason += " [" + std::to_string(ruled_out.size()) +
                    " other pose(s) fit as well but lie outside the motion prior]";
    return;
  }
  const Alternative& nearest = *std::min_element(
      rivals.begin(), rivals.end(),
      [](const Alternative& a, const Alternative& b) { return a.apart_m < b.apart_m; });
  first.valid = false;
  first.ambiguous = true;
  first.refusal = {RefusalTest::kAmbiguous, nearest.apart_m, config.refine.max_distance_coarse_m};
  char line[320];
  std::snprintf(line, sizeof(line),
                " [ambiguous: %s (score %.3f) and %s (score %.3f, images agree %.2f) both fit the "
                "scans, %.2f m apart over the source surface; the check tells poses apart only "
                "beyond %.2f m, so the pair alone cannot choose: give a motion prior]",
                PathName(first.path).c_str(), first.verification.score, nearest.name.c_str(),
                nearest.score, nearest.brightness_rank_correlation, nearest.apart_m,
                config.refine.max_distance_coarse_m);
  first.reason += line;
}

}  // namespace zeroreg
