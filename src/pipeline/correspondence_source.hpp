// Where 3D correspondences come from. The pipeline asks one source for correspondences and hands
// them to the estimator; swapping the source is how the object level (§3.3-3.4) and the paper's
// "w/o object level" ablation (Table 4 row a: whole-image features) share one pipeline.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "pipeline/stage_timer.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct CorrespondenceSet {
  std::vector<Correspondence> correspondences;
  int num_keypoints_source = 0;  // keypoints with valid 3D, over all views
  int num_keypoints_target = 0;
  std::string path;  // RegistrationResult::path; empty = the source's name()
  std::vector<ObjectSummary> source_objects, target_objects;
  std::vector<ObjectMatchSummary> object_matches;
  // Set by sources that can fall back to whole-image matching when their own correspondences do
  // not give a valid registration; computes them on demand.
  std::function<std::vector<Correspondence>()> whole_image_fallback;
};

class CorrespondenceSource {
 public:
  virtual ~CorrespondenceSource() = default;
  virtual std::string name() const = 0;  // recorded in RegistrationResult::path
  virtual CorrespondenceSet Find(const Scan& source, const Scan& target,
                                 StageTimer& timer) const = 0;
};

}  // namespace zeroreg
