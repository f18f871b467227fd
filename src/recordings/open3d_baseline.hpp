// Open3D's multiway registration recipe (open3d_multiway.hpp) run on two recordings as
// MergeRecordings runs zeroreg: the same keyframes (the co-visibility rule of RecordingsConfig),
// each keyframe's depth back-projected, every keyframe pair tried, B placed by the optimised
// graph. `zeroreg eval sessions --method open3d-multiway` measures it on the protocol of
// ../shared/sessions beside zeroreg's own merge (docs/RECORDINGS.md).
#pragma once

#include "recordings/open3d_multiway.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg {

// Fills keyframes (T_before, T_after), candidates (every loop edge that passed the fitness test:
// "accepted" when the line process kept it, "inconsistent" when it pruned it; T_u_v maps keyframe
// v into u), trajectories (every frame with a pose, moved with its keyframe), T_A_B and found,
// and one stage report per step. Writes nothing.
RecordingsResult MergeWithOpen3dMultiway(const RecordingInput& a, const RecordingInput& b,
                                         const RecordingsConfig& config,
                                         const MultiwayConfig& multiway = {});

}  // namespace zeroreg
