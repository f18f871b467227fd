#include "recordings/open3d_baseline.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "estimate/lift.hpp"
#include "estimate/voxel_filter.hpp"
#include "recordings/keyframes.hpp"
#include "recordings/stage_clock.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

namespace {

// The frame ids of a recording's range, in order; with poses, only the frames that have one.
std::vector<int> RecordingFrames(const RecordingInput& input, const Dataset& dataset) {
  std::vector<int> ids;
  for (int id : dataset.FrameIds()) {
    if (id < input.first_frame) continue;
    if (input.last_frame >= input.first_frame && id > input.last_frame) break;
    if (!input.T_frame_camera.empty() && input.T_frame_camera.count(id) == 0) continue;
    ids.push_back(id);
  }
  return ids;
}

}  // namespace

RecordingsResult MergeWithOpen3dMultiway(const RecordingInput& a, const RecordingInput& b,
                                         const RecordingsConfig& config,
                                         const Open3dBaselineConfig& baseline) {
  RecordingsResult result;
  std::vector<MultiwayKeyframe> keyframes;
  const RecordingInput* inputs[2] = {&a, &b};
  const bool fragments = baseline.frames_per_fragment > 0;
  {
    StageClock clock(fragments ? "fragments" : "keyframes", &result.stages);
    KeyframeConfig kc;
    kc.covisibility_threshold = config.keyframe_covisibility;
    kc.fallback_every = config.keyframe_every;
    for (int r = 0; r < 2; ++r) {
      const RecordingInput& input = *inputs[r];
      DatasetOptions options;
      options.depth_scale = input.depth_scale;
      const std::unique_ptr<Dataset> dataset = OpenDataset(input.root, options);
      const std::vector<int> ids = RecordingFrames(input, *dataset);
      if (fragments && input.T_frame_camera.empty()) {
        throw InputError(input.root +
                         ": the Open3D baseline fuses fragments with the recording's poses; it "
                         "has none");
      }
      if (fragments) {
        // make_fragments: every frames_per_fragment consecutive frames, in the first one's frame.
        for (std::size_t first = 0; first < ids.size();
             first += static_cast<std::size_t>(baseline.frames_per_fragment)) {
          const std::size_t count =
              std::min(static_cast<std::size_t>(baseline.frames_per_fragment), ids.size() - first);
          const Transform& T_rec_first = input.T_frame_camera.at(ids[first]);
          const Transform T_first_rec = T_rec_first.inverse();
          std::vector<Eigen::Vector3d> merged;
          for (std::size_t i = first; i < first + count; ++i) {
            const Transform T_first_camera = T_first_rec * input.T_frame_camera.at(ids[i]);
            const View view = dataset->LoadFrame(ids[i]);
            for (const Eigen::Vector3d& p :
                 BackProjectView(view, baseline.pixel_stride, 0.1, baseline.max_depth_m)) {
              merged.push_back(T_first_camera.topLeftCorner<3, 3>() * p +
                               T_first_camera.topRightCorner<3, 1>());
            }
          }
          std::vector<Eigen::Vector3d> points =
              VoxelDownSample(merged, {}, baseline.fragment_voxel_m).points;
          if (config.progress) {
            std::fprintf(stderr, "open3d multiway: fragment of %s frames %d-%d: %zu points\n",
                         r == 0 ? "A" : "B", ids[first], ids[first + count - 1], points.size());
          }
          if (points.empty()) continue;
          keyframes.push_back({r, std::move(points), T_rec_first});
          RecordingKeyframe k;
          k.recording = r;
          k.frame = ids[first];
          k.T_before = T_rec_first;
          result.keyframes.push_back(k);
        }
        continue;
      }
      KeyframeSelector selector(kc);
      for (int id : ids) {
        std::optional<Transform> pose;
        if (!input.T_frame_camera.empty()) pose = input.T_frame_camera.at(id);
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
    m = RegisterMultiway(keyframes, baseline.multiway, [&](int done, int total) {
      if (config.progress && (done % 10 == 0 || done == total)) {
        std::fprintf(stderr, "\ropen3d multiway: %d/%d node pairs", done, total);
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
