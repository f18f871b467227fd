#include "pipeline/hypotheses.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

#include "estimate/lift.hpp"
#include "features/fpfh.hpp"

namespace zeroreg {
namespace {

// Ranking of two finished results by the judge: validity first (the check passed and the
// correspondences support the estimate), then how well the scans agree.
bool Better(const RegistrationResult& a, const RegistrationResult& b) {
  if (a.valid != b.valid) return a.valid;
  if (a.count_test_passed != b.count_test_passed) return a.count_test_passed;
  return a.verification.score > b.verification.score;
}

// The extra sources' estimator and count test (HypothesesConfig documents why).
PipelineConfig ExtraSourceConfig(const PipelineConfig& config) {
  PipelineConfig e = config;
  e.ransac.estimator = config.hypotheses.estimator;
  e.ransac.min_inlier_ratio = config.hypotheses.min_inlier_ratio;
  return e;
}

}  // namespace

void Adopt(RegistrationResult winner, RegistrationResult* result) {
  winner.source_objects = std::move(result->source_objects);
  winner.target_objects = std::move(result->target_objects);
  winner.object_matches = std::move(result->object_matches);
  winner.rejected_object_matches = result->rejected_object_matches;
  winner.num_keypoints_source = result->num_keypoints_source;
  winner.num_keypoints_target = result->num_keypoints_target;
  *result = std::move(winner);
}

bool Disagree(double apart_m, const PipelineConfig& config) {
  return apart_m > config.refine.max_distance_coarse_m;
}

double EstimateDisplacementRms(const RegistrationResult& a, const RegistrationResult& b) {
  double sum = 0.0;
  size_t n = 0;
  const Eigen::Matrix3d Ra = a.T_target_source.topLeftCorner<3, 3>();
  const Eigen::Matrix3d Rb = b.T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d ta = a.T_target_source.topRightCorner<3, 1>();
  const Eigen::Vector3d tb = b.T_target_source.topRightCorner<3, 1>();
  for (const RegistrationResult* r : {&a, &b}) {
    for (const Correspondence& c : r->correspondences) {
      sum += ((Ra * c.source + ta) - (Rb * c.source + tb)).squaredNorm();
      ++n;
    }
  }
  return n == 0 ? 0.0 : std::sqrt(sum / static_cast<double>(n));
}

double PointDisplacementRms(const std::vector<SurfacePoint>* surface, const Transform& a,
                            const Transform& b) {
  if (surface == nullptr || surface->empty()) return 0.0;
  double sum = 0.0;
  for (const SurfacePoint& s : *surface) {
    const Eigen::Vector3d& p = s.point;
    sum += ((a * p.homogeneous()).head<3>() - (b * p.homogeneous()).head<3>()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(surface->size()));
}

bool JudgeImageRival(const PipelineConfig& config, const PipelineConfig& effective,
                     const HypothesisInputs& inputs, const JudgeFn& judge, StageTimer& timer,
                     RegistrationResult* result) {
  const bool degenerate = config.hypotheses.enabled && config.hypotheses.image_rival_degenerate &&
                          result->verification.degenerate;
  const bool rescued = config.hypotheses.enabled && config.hypotheses.image_rival_rescued &&
                       inputs.object_rescued_by_icp;
  const bool single = config.hypotheses.enabled && config.hypotheses.image_rival_single &&
                      result->object_matches.size() == 1;
  if (!(config.hypotheses.image_rival || degenerate || rescued || single) ||
      !config.verify.enabled || !result->valid || result->path != "object" || !inputs.whole_image) {
    return false;
  }
  timer.Restart();
  RegistrationResult rival = judge("image-rival", inputs.whole_image(), effective);
  timer.Mark("hypothesis image-rival");
  const double apart_m = EstimateDisplacementRms(*result, rival);
  const bool disagree = Disagree(apart_m, config);
  char line[240];
  std::snprintf(line, sizeof(line), "image-rival: %s, score %.3f, %.3f m RMS from %s",
                rival.valid ? "valid" : "not valid", rival.verification.score, apart_m,
                result->path.c_str());
  std::vector<CandidateSummary> all = result->candidates;
  all.insert(all.end(), rival.candidates.begin(), rival.candidates.end());
  char object_summary[120];
  std::snprintf(object_summary, sizeof(object_summary), "%s: score %.3f", result->path.c_str(),
                result->verification.score);
  // Degenerate geometry: the check cannot see the open motion, the correspondences fix it, and
  // the estimate more of them support wins where the two differ by more than ICP's final gate
  // over the source scan's surface (closer, they are the same answer and the object path keeps
  // it). Over the correspondences alone they can look alike: on hololens-gap5 250 -> 255 the two
  // lay 3 cm apart at one object's correspondences and 2.5 deg / 14 cm apart at the camera.
  const double apart_surface_m =
      PointDisplacementRms(inputs.source_surface, result->T_target_source, rival.T_target_source);
  const bool better_supported = degenerate && rival.valid &&
                                apart_surface_m > config.refine.max_distance_final_m &&
                                rival.num_inliers > result->num_inliers;
  // Rescued by ICP: the object's correspondences did not make the scans agree, so nothing but
  // the check speaks for the estimate, and the check picks between the two where they differ.
  // In degenerate geometry the score cannot tell the two apart: that case is the degenerate
  // rule's (by inliers), or, with that rule off, the object path keeps it.
  // One object match: nothing but that match and the check speak for the estimate (the same
  // rule as a rescued one).
  const bool better_scored = (rescued || single) && !result->verification.degenerate &&
                             rival.valid && apart_surface_m > config.refine.max_distance_final_m &&
                             rival.verification.score > result->verification.score;
  char support[200];
  std::snprintf(support, sizeof(support),
                "; inliers %d (%s) against %d (image-rival), %.3f m RMS apart over the source "
                "surface",
                result->num_inliers, result->path.c_str(), rival.num_inliers, apart_surface_m);
  // Which rule, if any, lets the rival win, and what the reason says of it (the surface support
  // figures only where the degenerate, rescued or single-match rule was asked).
  std::string asked_support = degenerate || rescued || single ? support : "";
  const char* why = nullptr;
  if (config.hypotheses.image_rival && rival.valid && disagree &&
      rival.verification.score > result->verification.score) {
    why = "the object path's estimate disagreed with the whole-image one and scored lower";
    asked_support.clear();  // decided by the score and the correspondences' distance alone
  } else if (better_supported) {
    why = "degenerate geometry: the whole-image estimate is supported by more correspondences";
  } else if (better_scored) {
    why = rescued ? "the object path's estimate passed the check only after ICP, and the "
                    "whole-image estimate scores higher"
                  : "the object path's estimate rests on one object match, and the whole-image "
                    "estimate scores higher";
  }
  if (why != nullptr) {
    Adopt(std::move(rival), result);
    result->reason += std::string(" [") + why + ": " + object_summary + "; " + line +
                      asked_support + "; chosen: image-rival]";
  } else {
    result->reason +=
        std::string(" [checked against the whole-image estimate: ") + line + asked_support + "]";
  }
  result->candidates = std::move(all);
  return true;
}

bool WantMoreHypotheses(const PipelineConfig& config, const RegistrationResult& result) {
  return config.hypotheses.enabled && config.verify.enabled &&
         (config.hypotheses.always || !result.valid);
}

std::vector<Correspondence> GeometryCorrespondences(const Scan& source, const Scan& target,
                                                    const PipelineConfig& config) {
  const HypothesesConfig& h = config.hypotheses;
  FpfhParams params;
  params.voxel_m = h.geometry_voxel_m;
  const FpfhCloud s = ComputeFpfh(ScanPoints(source, PixelGrid{h.geometry_pixel_stride},
                                             config.lift.min_depth_m, config.lift.max_depth_m),
                                  params);
  const FpfhCloud t = ComputeFpfh(ScanPoints(target, PixelGrid{h.geometry_pixel_stride},
                                             config.lift.min_depth_m, config.lift.max_depth_m),
                                  params);
  std::vector<Correspondence> out;
  for (const FeaturePair& m : MutualFeatureMatches(s, t, config.threads)) {
    Correspondence c;
    c.source = s.points[static_cast<size_t>(m.source)];
    c.target = t.points[static_cast<size_t>(m.target)];
    c.score = m.score;
    c.view = -1;  // not from an image
    c.target_view = -1;
    out.push_back(c);
  }
  return out;
}

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

void JudgeMoreHypotheses(const Scan& source, const Scan& target, const PipelineConfig& config,
                         const HypothesisInputs& inputs, const JudgeFn& judge,
                         const JudgeFn& judge_object_pairs, StageTimer& timer,
                         RegistrationResult* result) {
  const HypothesesConfig& h = config.hypotheses;
  const PipelineConfig extra = ExtraSourceConfig(config);
  std::vector<RegistrationResult> tried;
  // Parallel to `tried`: why judge_extra refused a result the check passed ("" = it did not).
  std::vector<std::string> refused;
  // Every extra source's result passes through here (HypothesesConfig::refuse_degenerate).
  // `without_images`: the source's correspondences come from no image (geometry, centroids), so
  // the images must agree where the depth does (min_brightness_rank_correlation).
  auto judge_extra = [&](const std::string& path, std::vector<Correspondence> correspondences,
                         const PipelineConfig& effective, const JudgeFn& judge_with = nullptr,
                         bool without_images = false) {
    RegistrationResult r =
        (judge_with ? judge_with : judge)(path, std::move(correspondences), effective);
    std::string why;
    if (h.refuse_degenerate && r.valid && r.verification.degenerate) {
      r.valid = false;
      why = "refused: degenerate geometry";
      r.reason +=
          "; refused: the geometry is degenerate and this source's correspondences are "
          "too weak to fix the open motion";
    }
    const double rho = r.verification.brightness_rank_correlation;
    if (without_images && r.valid && std::isfinite(rho) &&
        rho < h.min_brightness_rank_correlation) {
      r.valid = false;
      why = "refused: the images disagree where the depth agrees";
      char note[200];
      std::snprintf(note, sizeof(note),
                    "; refused: the images disagree where the depth agrees (rank correlation of "
                    "their brightness %.2f, need %.2f)",
                    rho, h.min_brightness_rank_correlation);
      r.reason += note;
    }
    refused.push_back(why);
    return r;
  };
  timer.Restart();
  // (a) The object correspondences again, when the extra estimator differs from the method's.
  if (!inputs.object_correspondences.empty() && h.estimator != config.ransac.estimator) {
    tried.push_back(judge_extra("object " + h.estimator, inputs.object_correspondences, extra));
    timer.Mark("hypothesis object");
  }
  // (b) Whole-image correspondences, unless the fallback already estimated them the same way.
  if (h.image && inputs.whole_image &&
      !(inputs.whole_image_tried && h.estimator == config.ransac.estimator)) {
    tried.push_back(judge_extra("image " + h.estimator, inputs.whole_image(), extra));
    timer.Mark("hypothesis image");
  }
  // (c) Geometry. Correspondences between voxel centres are off by up to about a voxel even when
  // right, so their inlier distance is 1.5 voxels (as the FPFH baseline's, --method fpfh).
  if (h.geometry) {
    PipelineConfig geometry = extra;
    geometry.ransac.inlier_threshold_m =
        std::max(config.ransac.inlier_threshold_m, 1.5 * h.geometry_voxel_m);
    tried.push_back(judge_extra("geometry " + h.estimator,
                                GeometryCorrespondences(source, target, config), geometry, nullptr,
                                /*without_images=*/true));
    timer.Mark("hypothesis geometry");
  }
  // (d) Object centroids, judged at the centroid distance of the paper's Table 4 row (b).
  if (h.objects) {
    std::vector<Correspondence> pairs = ObjectPairCorrespondences(*result);
    if (pairs.size() >= 3) {
      PipelineConfig objects = extra;
      objects.ransac.inlier_threshold_m = config.method.object_centroid_threshold_m;
      objects.ransac.min_inliers = 3;
      tried.push_back(judge_extra("object-pairs " + h.estimator, std::move(pairs), objects,
                                  judge_object_pairs, /*without_images=*/true));
      timer.Mark("hypothesis object-pairs");
    }
  }
  // (e) The whole images with the source's turned, only when nothing above is valid: a camera
  // rolled by a quarter or half turn leaves XFeat few right matches, and every other source has
  // had its chance. Only the turn that shares the most distinctive matches with the target is
  // matched and judged (MatchTurnedWholeImages), and none when the unturned images share as many.
  // Turned the right way, these are the fallback's own correspondences, so they are estimated as
  // the fallback's are (its estimator and count test: an inlier ratio, which a turn matched by
  // chance does not reach) and may be valid in degenerate geometry, where the image
  // correspondences fix the open motion (hololens-gap1 3 <- 4 with the source upside down: a wall,
  // 0.3 deg off); `judge` holds the refinement to the extra sources' rules.
  const bool any_valid =
      result->valid ||
      std::any_of(tried.begin(), tried.end(), [](const RegistrationResult& r) { return r.valid; });
  std::string turned_scores;
  if (h.turned_images && inputs.whole_image_turned && !any_valid) {
    TurnedWholeImage turned = inputs.whole_image_turned();
    const std::array<int, 4>& o = turned.overlap_scores;
    turned_scores = "image-turned: distinctive matches at 0/90/180/270 deg " +
                    std::to_string(o[0]) + "/" + std::to_string(o[1]) + "/" + std::to_string(o[2]) +
                    "/" + std::to_string(o[3]);
    if (turned.quarter_turns > 0) {
      tried.push_back(judge("image-turned-" + std::to_string(90 * turned.quarter_turns) + " " +
                                config.ransac.estimator,
                            std::move(turned.correspondences), config));
      refused.emplace_back();
    } else {
      turned_scores += turned.best_turn > 0
                           ? ", none matched: fewer than " + std::to_string(h.turned_min_matches) +
                                 " for the best turn"
                           : ", no turn above the unturned images";
    }
    timer.Mark("hypothesis turned images");
  }

  // The judge: the best of the method's result and every hypothesis. Only a valid hypothesis
  // replaces the method's result: among invalid ones the score says little (redkitchen-cross
  // 490-858: an invalid geometry estimate 178 deg off outscored the fallback's 13 deg one).
  // With hypotheses.always the method's estimate may be valid already. A source that disagrees
  // with it (farther apart than ICP's widest gate, as for the image rival) does not replace it:
  // the check's score cannot choose between two poses it accepts (hololens-gap5 162-167: the
  // geometry source's pose 0.9 m off covered 45 % of the scans and outscored the method's right
  // one, 13 %), and the method's estimate rests on its own correspondences.
  const bool method_valid = result->valid;
  int best = -1, disagreeing = 0;
  for (size_t k = 0; k < tried.size(); ++k) {
    const RegistrationResult& incumbent = best < 0 ? *result : tried[static_cast<size_t>(best)];
    if (!tried[k].valid || !Better(tried[k], incumbent)) continue;
    if (method_valid && Disagree(EstimateDisplacementRms(tried[k], *result), config)) {
      ++disagreeing;
      continue;
    }
    best = static_cast<int>(k);
  }
  std::vector<CandidateSummary> all = result->candidates;
  std::string summary;
  // `refusal`: why judge_extra refused it; otherwise a result the check passed that is not valid
  // is one whose refinement is another accepted pose (Refine).
  auto describe = [](const RegistrationResult& r, const std::string& refusal) {
    const char* verdict = r.valid                ? "valid"
                          : !r.count_test_passed ? "no consensus"
                          : !refusal.empty()     ? refusal.c_str()
                          : r.outside_prior      ? "outside the motion prior"
                          : r.verification.passed
                              ? "not valid: another pose passes the check as well"
                              : "refused by the check";
    char line[200];
    std::snprintf(line, sizeof(line), "%s: %s, score %.3f", r.path.c_str(), verdict,
                  r.verification.score);
    return std::string(line);
  };
  summary += describe(*result, "");
  for (size_t k = 0; k < tried.size(); ++k) {
    const RegistrationResult& r = tried[k];
    all.insert(all.end(), r.candidates.begin(), r.candidates.end());
    summary += "; " + describe(r, refused[k]);
  }
  if (!turned_scores.empty()) summary += "; " + turned_scores;
  if (best >= 0) Adopt(std::move(tried[static_cast<size_t>(best)]), result);
  result->candidates = std::move(all);
  if (disagreeing > 0) {
    summary += "; " + std::to_string(disagreeing) +
               " valid, higher-scoring, disagreeing with the method's valid estimate: not taken";
  }
  result->reason += " [hypotheses: " + summary + "; chosen: " + result->path + "]";
}

}  // namespace zeroreg
