// The arbiter's decision rules on stand-in candidates: what each rule decides from the fields of
// judged candidates, without images, so that a tuning change of the sources or the check does not
// mean finding a real pair that still shows the rule. (The real pairs of arbiter_test.cpp keep
// what the rules give on real data.)
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/arbiter.hpp"
#include "rigid_motion.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

RegistrationResult Candidate(bool valid, bool count, double score) {
  RegistrationResult r;
  r.valid = valid;
  r.count_test_passed = count;
  r.verification.score = score;
  return r;
}

TEST(ArbiterRules, BetterRanksValidityThenCountEvidenceThenScore) {
  // Valid beats invalid whatever the scores and counts.
  EXPECT_TRUE(Better(Candidate(true, true, 0.1), Candidate(false, true, 0.9)));
  EXPECT_FALSE(Better(Candidate(false, true, 0.9), Candidate(true, true, 0.1)));
  // Among invalid ones, count evidence beats a higher score.
  EXPECT_TRUE(Better(Candidate(false, true, 0.1), Candidate(false, false, 0.9)));
  EXPECT_FALSE(Better(Candidate(false, false, 0.9), Candidate(false, true, 0.1)));
  // Then the check's score.
  EXPECT_TRUE(Better(Candidate(true, true, 0.5), Candidate(true, true, 0.4)));
  EXPECT_FALSE(Better(Candidate(true, true, 0.4), Candidate(true, true, 0.5)));
  // A tie is not better: the candidate held first stays.
  EXPECT_FALSE(Better(Candidate(true, true, 0.4), Candidate(true, true, 0.4)));
}

Judged Held(bool valid, bool valid_before_icp, bool degenerate, int object_matches) {
  Judged j;
  j.result.valid = valid;
  j.result.verification.degenerate = degenerate;
  j.result.object_matches.assign(static_cast<size_t>(object_matches), ObjectMatchSummary());
  j.valid_before_icp = valid_before_icp;
  return j;
}

TEST(ArbiterRules, DoubtOfAValidObjectCandidate) {
  const PipelineConfig config;  // the defaults: every doubt on, image_rival off
  // Decisive: valid before ICP, not degenerate, two object matches.
  Doubt d = DoubtOf(config, Held(true, true, false, 2));
  EXPECT_FALSE(d.degenerate || d.rescued || d.single);
  EXPECT_FALSE(d.any(config));
  // Each reason alone.
  d = DoubtOf(config, Held(true, true, true, 2));
  EXPECT_TRUE(d.degenerate && !d.rescued && !d.single);
  d = DoubtOf(config, Held(true, false, false, 2));
  EXPECT_TRUE(!d.degenerate && d.rescued && !d.single);
  d = DoubtOf(config, Held(true, true, false, 1));
  EXPECT_TRUE(!d.degenerate && !d.rescued && d.single);
  EXPECT_TRUE(d.any(config));
  // Rescued needs a valid result: an invalid one was not rescued.
  EXPECT_FALSE(DoubtOf(config, Held(false, false, false, 2)).rescued);
  // Each switch turns its own doubt off; hypotheses.enabled turns them all off.
  PipelineConfig off = config;
  off.hypotheses.image_rival_degenerate = false;
  EXPECT_FALSE(DoubtOf(off, Held(true, true, true, 2)).degenerate);
  off = config;
  off.hypotheses.image_rival_rescued = false;
  EXPECT_FALSE(DoubtOf(off, Held(true, false, false, 2)).rescued);
  off = config;
  off.hypotheses.image_rival_single = false;
  EXPECT_FALSE(DoubtOf(off, Held(true, true, false, 1)).single);
  off = config;
  off.hypotheses.enabled = false;
  d = DoubtOf(off, Held(true, false, true, 1));
  EXPECT_FALSE(d.degenerate || d.rescued || d.single);
  // hypotheses.image_rival doubts every valid object candidate.
  PipelineConfig always = config;
  always.hypotheses.image_rival = true;
  EXPECT_TRUE(DoubtOf(always, Held(true, true, false, 2)).any(always));
}

RegistrationResult Rival(bool valid, double score, int inliers) {
  RegistrationResult r = Candidate(valid, true, score);
  r.num_inliers = inliers;
  return r;
}

TEST(ArbiterRules, RivalRuleByScoreWhereTheEstimatesDisagree) {
  PipelineConfig config;
  config.hypotheses.image_rival = true;
  const double coarse = config.refine.max_distance_coarse_m;
  const RegistrationResult held = Rival(true, 0.35, 30);
  const Doubt none;
  // Farther apart than ICP's widest gate and scoring higher: the rival.
  EXPECT_EQ(RivalRule(config, none, held, Rival(true, 0.47, 5), {1.5 * coarse, 1.5 * coarse}),
            RivalWin::kScore);
  // At the gate (not beyond it) they are one answer; a lower score, or an invalid rival, loses.
  EXPECT_EQ(RivalRule(config, none, held, Rival(true, 0.47, 5), {coarse, coarse}), RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, none, held, Rival(true, 0.30, 5), {1.5 * coarse, 1.5 * coarse}),
            RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, none, held, Rival(false, 0.90, 90), {1.5 * coarse, 1.5 * coarse}),
            RivalWin::kNone);
  // Without hypotheses.image_rival (the default) and no doubt, nothing replaces the held one.
  config.hypotheses.image_rival = false;
  EXPECT_EQ(RivalRule(config, none, held, Rival(true, 0.47, 5), {1.5 * coarse, 1.5 * coarse}),
            RivalWin::kNone);
}

TEST(ArbiterRules, RivalRuleInDegenerateGeometryBySupport) {
  const PipelineConfig config;
  const double final_gate = config.refine.max_distance_final_m;
  RegistrationResult held = Rival(true, 0.537, 33);
  held.verification.degenerate = true;
  Doubt degenerate;
  degenerate.degenerate = true;
  // More inliers and distinct over the source surface: the rival, whatever the scores say.
  EXPECT_EQ(RivalRule(config, degenerate, held, Rival(true, 0.2, 330), {0, 3 * final_gate}),
            RivalWin::kSupport);
  // Not distinct (at ICP's final gate), not more inliers, or not valid: the held one stays.
  EXPECT_EQ(RivalRule(config, degenerate, held, Rival(true, 0.9, 330), {0, final_gate}),
            RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, degenerate, held, Rival(true, 0.9, 33), {0, 3 * final_gate}),
            RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, degenerate, held, Rival(false, 0.9, 330), {0, 3 * final_gate}),
            RivalWin::kNone);
}

TEST(ArbiterRules, RivalRuleForARescuedOrSingleMatchEstimateByScore) {
  const PipelineConfig config;
  const double final_gate = config.refine.max_distance_final_m;
  const RegistrationResult held = Rival(true, 0.316, 7);
  Doubt rescued, single, both;
  rescued.rescued = true;
  single.single = true;
  both.rescued = both.single = true;
  const RivalMeasure distinct{0, 3 * final_gate};
  EXPECT_EQ(RivalRule(config, rescued, held, Rival(true, 0.484, 1), distinct),
            RivalWin::kRescuedScore);
  EXPECT_EQ(RivalRule(config, single, held, Rival(true, 0.484, 1), distinct),
            RivalWin::kSingleScore);
  EXPECT_EQ(RivalRule(config, both, held, Rival(true, 0.484, 1), distinct),
            RivalWin::kRescuedScore);
  // A lower score, the same answer, or an invalid rival: the held one stays.
  EXPECT_EQ(RivalRule(config, rescued, held, Rival(true, 0.30, 90), distinct), RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, rescued, held, Rival(true, 0.484, 90), {0, final_gate}),
            RivalWin::kNone);
  EXPECT_EQ(RivalRule(config, single, held, Rival(false, 0.484, 90), distinct), RivalWin::kNone);
  // In degenerate geometry the score cannot tell the two apart: these rules stand aside (the
  // support rule decides when that doubt is raised).
  RegistrationResult degenerate_held = held;
  degenerate_held.verification.degenerate = true;
  EXPECT_EQ(RivalRule(config, both, degenerate_held, Rival(true, 0.484, 1), distinct),
            RivalWin::kNone);
}

// Decide with a stand-in judge answering each source by its path name (a path not listed is
// judged invalid without count evidence); no whole images unless `whole_image`.
struct Answer {
  bool valid = false;
  bool count = true;
  double score = 0.0;
  double offset_m = 0.0;  // the candidate's transform: a shift along x
  bool passed = false;    // its check passed (valid, or refused after the check)
};
struct Decided {
  RegistrationResult result;
  std::vector<std::string> asked;
};
Decided Decide(const PipelineConfig& base, const std::map<std::string, Answer>& answers,
               const std::optional<MotionPrior>& prior, bool whole_image = false) {
  Decided out;
  PipelineConfig config = base;
  config.hypotheses.geometry = false;  // no depth here
  Prepared source, target;
  WholeImageMatches images(whole_image ? std::function<std::vector<Correspondence>()>([] {
    return std::vector<Correspondence>(8, Correspondence());
  })
                                       : nullptr);
  RegistrationResult scans;
  PairInputs pair{source, target, config, prior, nullptr, nullptr, {}, &images, &scans, &config};
  const JudgeFn judge = [&](Proposal p, StageTimer*) {
    const std::string name = PathName(p.path);
    out.asked.push_back(name);
    Judged j;
    RegistrationResult& r = j.result;
    r.path = p.path;
    const auto it = answers.find(name);
    const Answer a = it != answers.end() ? it->second : Answer{false, false};
    r.valid = a.valid;
    r.count_test_passed = a.count;
    r.verification.score = a.score;
    r.T_target_source = testing::ShiftedAlongX(a.offset_m);
    j.valid_before_icp = a.valid;
    CandidateSummary candidate;
    candidate.name = name;
    candidate.T_target_source = r.T_target_source;
    candidate.passed = a.valid || a.passed;
    r.candidates.push_back(candidate);
    return j;
  };
  StageTimer timer;
  Proposal method;
  method.path = {PathSource::kObject};
  out.result = Arbiter(judge, pair, timer).Decide(method, scans);
  return out;
}

// Step 4 of the rule: ICP from the motion prior only when nothing valid is held, taken only when
// valid.
TEST(ArbiterRules, ThePriorIsAskedOnlyWhenNothingIsValidAndTakenOnlyWhenValid) {
  PipelineConfig config;
  config.hypotheses.enabled = false;  // steps 1 and 4 alone
  const MotionPrior prior{testing::ShiftedAlongX(0.05)};
  // Nothing valid: the prior is asked and its valid candidate taken.
  Decided d =
      Decide(config, {{"object", {false, true, 0.1, 2.0}}, {"prior", {true, true, 0.4}}}, prior);
  EXPECT_EQ(d.asked, (std::vector<std::string>{"object", "prior"}));
  EXPECT_TRUE(d.result.valid);
  EXPECT_EQ(d.result.path, Path{PathSource::kPrior});
  EXPECT_TRUE(ComesFromMotionPrior(d.result));
  // An invalid candidate from the prior does not replace the held one.
  d = Decide(config, {{"object", {false, true, 0.3, 2.0}}, {"prior", {false, true, 0.2}}}, prior);
  EXPECT_EQ(d.asked, (std::vector<std::string>{"object", "prior"}));
  EXPECT_FALSE(d.result.valid);
  EXPECT_EQ(d.result.path, Path{PathSource::kObject});
  // A valid method candidate: the prior is not asked.
  d = Decide(config, {{"object", {true, true, 0.3, 0.05}}}, prior);
  EXPECT_EQ(d.asked, std::vector<std::string>{"object"});
  // No prior, or no check to judge where ICP from it lands: not asked.
  EXPECT_EQ(Decide(config, {{"object", {false, true, 0.3}}}, std::nullopt).asked,
            std::vector<std::string>{"object"});
  PipelineConfig unchecked = config;
  unchecked.verify.enabled = false;
  d = Decide(unchecked, {{"object", {false, true, 0.3}}}, prior);
  EXPECT_EQ(d.asked, std::vector<std::string>{"object"});
}

// The candidates are marked: chosen = the returned transform; outside_prior = passed the check,
// beyond the prior's tolerance.
TEST(ArbiterRules, CandidatesAreMarkedChosenAndOutsideThePrior) {
  PipelineConfig config;
  config.hypotheses.enabled = false;
  const MotionPrior prior{testing::ShiftedAlongX(0.0), 15.0, 0.30};
  // The method's candidate passes 1 m from the prior (the judge made it invalid); ICP from the
  // prior is valid.
  const Decided d =
      Decide(config, {{"object", {false, true, 0.3, 1.0, true}}, {"prior", {true, true, 0.4, 0.1}}},
             prior);
  ASSERT_EQ(d.result.candidates.size(), 2u);
  const CandidateSummary& object = d.result.candidates[0];
  const CandidateSummary& from_prior = d.result.candidates[1];
  EXPECT_TRUE(object.passed && object.outside_prior && !object.chosen);
  EXPECT_TRUE(from_prior.passed && !from_prior.outside_prior && from_prior.chosen);
}

// Step 2 needs the whole images: without them an invalid method candidate is held as it is.
TEST(ArbiterRules, WithoutWholeImagesNoFallbackIsAsked) {
  PipelineConfig config;
  config.hypotheses.enabled = false;
  Decided d = Decide(config, {{"object", {false, true, 0.2}}}, std::nullopt, false);
  EXPECT_EQ(d.asked, std::vector<std::string>{"object"});
  d = Decide(config, {{"object", {false, true, 0.2}}, {"image-fallback", {true, true, 0.3}}},
             std::nullopt, true);
  EXPECT_EQ(d.asked, (std::vector<std::string>{"object", "image-fallback"}));
  EXPECT_EQ(d.result.path, Path{PathSource::kImageFallback});
}

// Step 3: with hypotheses.always the extra sources are asked for a valid result too; without
// it, only while nothing valid is held.
TEST(ArbiterRules, ExtraSourcesAreAskedForAValidResultOnlyWithAlways) {
  // A valid object candidate without doubt (valid before ICP, no object match, not degenerate).
  PipelineConfig config;
  const std::map<std::string, Answer> answers = {{"object", {true, true, 0.3}}};
  Decided d = Decide(config, answers, std::nullopt, true);
  EXPECT_EQ(d.asked, std::vector<std::string>{"object"});
  config.hypotheses.always = true;
  d = Decide(config, answers, std::nullopt, true);
  // The whole images with the extra sources' estimator (the other sources have nothing to
  // propose here); invalid, so the held candidate stays.
  EXPECT_EQ(d.asked, (std::vector<std::string>{"object", "image clique"}));
  EXPECT_EQ(d.result.path, Path{PathSource::kObject});
}

}  // namespace
}  // namespace zeroreg
