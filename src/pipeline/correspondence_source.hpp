// Where 3D correspondences come from. The pipeline asks one source for correspondences and hands
// them to the estimator; swapping the source is how the object level (§3.3-3.4) and the paper's
// "w/o object level" ablation (Table 4 row a: whole-image features) share one pipeline.
//
// A source works in two steps so that what depends on one scan alone is computed once per scan
// (Pipeline::Prepare) and reused by every pair the scan is in: Perceive (per scan: features,
// detections, masks, objects) and Find (per pair: object matching, point matching).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "object_match/motion_agreement.hpp"
#include "objects/scene_objects.hpp"
#include "pipeline/image_correspondences.hpp"
#include "pipeline/stage_timer.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// Everything a source perceived in one scan. Immutable once made; shared read-only by the pairs.
struct PerceivedScan {
  std::vector<LiftedFeatures> view_features;  // per view, keypoints with usable depth
  std::vector<ViewLift> view_lifts;  // per view, how its keypoints were lifted (LiftForView)
  int num_keypoints = 0;             // CountKeypoints(view_features)
  SceneObjects objects;              // object sources only (§3.2)
  // Per observation of `objects`: the rows of its view's features whose keypoint lies inside its
  // mask (the candidates of §3.4's point matching).
  std::vector<std::vector<int>> observation_rows;
  std::vector<ObjectSummary> object_summaries;  // `objects` as RegistrationResult reports them
};

struct CorrespondenceSet {
  std::vector<Correspondence> correspondences;
  PathSource path = PathSource::kNone;  // RegistrationResult::path; kNone = the source's own
  std::vector<ObjectMatchSummary> object_matches;
  // Parallel to object_matches: each match's §3.4 point matches, before overlapping masks are
  // deduplicated (empty for the centroid-only flow).
  std::vector<MatchMotion> object_match_points;
  int rejected_object_matches = 0;  // RegistrationResult::rejected_object_matches
  // Set by sources that can fall back to whole-image matching when their own correspondences do
  // not give a valid registration; computes them on demand.
  std::function<std::vector<Correspondence>()> whole_image_fallback;
};

class CorrespondenceSource {
 public:
  virtual ~CorrespondenceSource() = default;
  virtual PathSource path() const = 0;  // recorded in RegistrationResult::path
  // Per-scan perception. Thread-safe: Pipeline::Register prepares its two scans concurrently (the
  // models serialise their own inference); the result depends on the scan and config only.
  virtual PerceivedScan Perceive(const Scan& scan, StageTimer& timer) const = 0;
  // Per-pair matching of two perceived scans (kept alive by the fallback, hence shared).
  virtual CorrespondenceSet Find(const std::shared_ptr<const PerceivedScan>& source,
                                 const std::shared_ptr<const PerceivedScan>& target,
                                 StageTimer& timer) const = 0;
};

}  // namespace zeroreg
