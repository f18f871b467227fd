#include "recordings/open3d_baseline.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include "estimate/lift.hpp"
#include "recordings/keyframes.hpp"
#include "recordings/stage_clock.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

RecordingsResult MergeWithOpen3dMultiway(const RecordingInput& a, const RecordingInput& b,
                                         const RecordingsConfig& config,
                                         const MultiwayConfig& multiway) {
  RecordingsResult result;
  std::vector<MultiwayKeyframe> keyframes;
  const RecordingInput* inputs[2] = {&a, &b};
  {
    StageClock clock("keyframes", &result.stages);
    KeyframeConfig kc;
    kc.covisibility_threshold = config.keyframe_covisibility;
    kc.fallback_every = config.keyframe_every;
    for (int r = 0; r < 2; ++r) {
      const RecordingInput& input = *inputs[r];
      DatasetOptions options;
      options.depth_scale = input.depth_scale;
      const std::unique_ptr<Dataset> dataset = OpenDataset(input.root, options);
      KeyframeSelector selector(kc);
      for (int id : dataset->FrameIds()) {
        if (id < input.first_frame) continue;
        if (input.last_frame >= input.first_frame && id > input.last_frame) break;
        std::optional<Transform> pose;
        if (!input.T_frame_camera.empty()) {
          const auto it = input.T_frame_camera.find(id);
          if (it == input.T_frame_camera.end()) continue;
          pose = it->second;
        }
        const View view = dataset->LoadFrame(id);
        if (!selector.Add(view, pose)) continue;
        // Every 2nd pixel: the recipe's 5 cm voxel holds many readings at any Kinect distance.
        keyframes.push_back({r, BackProjectView(view, 2, 0.1, 8.0), pose});
        RecordingKeyframe k;
        k.recording = r;
        k.frame = id;
        if (pose) k.T_before = *pose;
        result.keyframes.push_back(k);
      }
    }
  }
  if (keyframes.empty() || keyframes.front().recording != 0) {
    throw InputError(a.root + ": recording A has no keyframe");
  }
  MultiwayResult m;
  {
    StageClock clock("multiway", &result.stages);
    m = RegisterMultiway(keyframes, multiway, [&](int done, int total) {
      if (config.progress && (done % 100 == 0 || done == total)) {
        std::fprintf(stderr, "\ropen3d multiway: %d/%d keyframe pairs", done, total);
        if (done == total) std::fprintf(stderr, "\n");
      }
    });
  }
  for (const MultiwayEdge& e : m.edges) {
    if (!e.loop) continue;
    LoopCandidateResult c;
    c.u = e.target;
    c.v = e.source;
    c.valid = true;
    c.T_u_v = e.T_target_source;
    c.overlap = e.fitness;
    c.verdict = e.kept ? "accepted" : "inconsistent";
    c.path = "open3d-multiway";
    result.candidates.push_back(c);
  }
  for (size_t k = 0; k < result.keyframes.size(); ++k) {
    result.keyframes[k].T_after =
        m.placed[k] ? m.T_world_keyframe[k] : result.keyframes[k].T_before;
  }
  result.found = m.T_A_B.has_value();
  if (result.found) result.T_A_B = *m.T_A_B;
  result.reason = result.found ? "B placed by the optimised pose graph"
                               : "no keyframe pair between A and B passed the fitness test";
  result.trajectories = {PlacedTrajectory(a.T_frame_camera, result.keyframes, 0),
                         result.found ? PlacedTrajectory(b.T_frame_camera, result.keyframes, 1)
                                      : std::map<int, Transform>{}};
  return result;
}

}  // namespace zeroreg
