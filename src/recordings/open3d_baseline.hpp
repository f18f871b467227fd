// Open3D's multiway registration recipe (open3d_multiway.hpp) run on two recordings: the nodes are
// the recipe's fragments (its reconstruction system's make_fragments stage: every 100 consecutive
// frames of a recording in one cloud, here placed with the recording's own poses), every fragment
// pair tried, B placed by the optimised graph. With frames_per_fragment = 0 the nodes are
// MergeRecordings' keyframes instead (each keyframe's depth back-projected): every keyframe pair is
// then tried, which grows with the square of the keyframes (742 pairs on the redkitchen split,
// 16,836 on HoloLens). `zeroreg eval sessions --method open3d-multiway` measures it on the protocol
// of
// ../shared/sessions beside zeroreg's own merge (docs/RECORDINGS.md).
#pragma once

#include "recordings/open3d_multiway.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg {

// The make_fragments settings of Open3D's reconstruction system: fragments of 100 frames, depth up
// to 3 m (its config defaults). Its TSDF integration (5.9 mm voxels) is replaced by the frames'
// depth put together with the recording's poses and thinned to 1 cm: the TSDF took about a second
// of processor time per frame here, and the recipe registers the fragments at 5 cm anyway.
struct Open3dBaselineConfig {
  MultiwayConfig multiway;
  int frames_per_fragment = 100;  // n_frames_per_fragment; 0: keyframes as nodes
  double max_depth_m = 3.0;       // max_depth
  int pixel_stride = 4;           // every 4th pixel of every 4th row of each frame
  double fragment_voxel_m = 0.01;
};

// Fills keyframes (one per node: a fragment's first frame, or a keyframe; T_before, T_after),
// candidates (every loop edge that passed the fitness test: "accepted" when the line process kept
// it, "inconsistent" when it pruned it; T_u_v maps node v into u), trajectories (every frame with
// a pose, moved with its node), T_A_B and found, and one stage report per step. Writes nothing.
// Fragments need the recordings' poses (InputError without).
RecordingsResult MergeWithOpen3dMultiway(const RecordingInput& a, const RecordingInput& b,
                                         const RecordingsConfig& config,
                                         const Open3dBaselineConfig& baseline = {});

}  // namespace zeroreg
