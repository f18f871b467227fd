// What Pipeline::Prepare keeps of one scan (PreparedScan::Data), shared by the sources, the judge
// and the arbiter of the pair stage.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "estimate/icp.hpp"
#include "estimate/working_scale.hpp"
#include "pipeline/correspondence_source.hpp"
#include "verify/verify.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {

struct PreparedScan::Data {
  std::uint64_t pipeline_id = 0;  // the Pipeline that made it (its config decided all of it)
  // The scan in working units (src/estimate/working_scale.hpp): lengths divided by
  // working_scale; the scan as given when that is 1.
  Scan scan;
  double working_scale = 1.0;
  ScaleEvidence scale_evidence;                    // its median valid depth and depth noise
  std::shared_ptr<const Scan> original;            // the scan as given, when working_scale != 1
  std::shared_ptr<const PerceivedScan> perceived;  // features, detections, masks, objects
  std::vector<SurfacePoint> surface;               // verification samples (verify.enabled)
  IcpGeometry icp;                                 // ICP clouds per resolution (refine.enabled)
  std::vector<StageTime> timings;
  std::size_t memory_bytes = 0;
  // hypotheses.turned_images: the features of the turned colour images, made the first time a
  // pair with this scan as its source needs them (most scans never do), then shared by every such
  // pair (ExtractTurnedFeatures).
  mutable std::once_flag turned_once;
  mutable TurnedFeatures turned;
  // verify.mirror_min_matches: the features of the mirrored colour images, made the first time
  // a valid result with this scan as its source needs the mirror test (RefuseMirrorImage).
  mutable std::once_flag mirrored_once;
  mutable std::vector<LiftedFeatures> mirrored;
  // What `turned` and `mirrored` hold once made (MemoryBytes includes it from then on; 0 before).
  mutable std::atomic<std::size_t> turned_bytes{0};
};

using Prepared = PreparedScan::Data;

// What a prepared scan holds, for the library's own stages above the pair (the recordings' place
// recognition reads the features Prepare extracted). nullptr for an empty one.
const PreparedScan::Data* PreparedScanData(const PreparedScan& prepared);

// Heap bytes of one view's features: keypoints with their scores, descriptors, 3D points.
std::size_t LiftedFeaturesBytes(const LiftedFeatures& f);

}  // namespace zeroreg
