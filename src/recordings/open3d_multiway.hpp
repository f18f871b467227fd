// The baseline a user of Open3D builds today to merge two recordings or close loops: Open3D's
// multiway registration recipe (its reconstruction system's "register fragments" and "refine"
// stages) applied to keyframes, from Open3D 0.16's own C++ API (src/open3d_module/):
//   1. every keyframe's cloud down-sampled to a voxel, with FPFH features;
//   2. odometry edges between consecutive keyframes of a recording: the recording's poses (when
//      given) refined by point-to-plane ICP, else FPFH + RANSAC then ICP;
//   3. loop edges between every other pair of keyframes: FPFH + RANSAC, then ICP, kept when ICP's
//      fitness is above a threshold; uncertain (the line process may switch them off);
//   4. Open3D's GlobalOptimization (Levenberg-Marquardt with the line process of Choi et al.,
//      CVPR 2015), which prunes loop edges whose weight falls below a threshold.
// Nothing of zeroreg's registration is used: this is what zeroreg's own loop closure is compared
// against (docs/RECORDINGS.md).
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct MultiwayKeyframe {
  int recording = 0;                      // 0: recording A, 1: recording B
  std::vector<Eigen::Vector3d> points;    // back-projected depth in the camera frame, metres
  std::optional<Transform> T_rec_camera;  // pose in its recording's own frame, when known
};

struct MultiwayConfig {
  // Open3D's reconstruction system defaults: a 5 cm voxel, RANSAC and ICP gates of 1.5 voxels,
  // FPFH radius 5 voxels, RANSAC 1,000,000 iterations at 0.999 confidence.
  double voxel_m = 0.05;
  int ransac_max_iterations = 1000000;
  double ransac_confidence = 0.999;
  // A loop edge is kept when ICP's fitness (fraction of the source within the gate) is above this
  // (Open3D's multiway tutorial keeps pair edges above 0.3).
  double min_fitness = 0.3;
  // GlobalOptimizationOption of the recipe's fragment stage: loop closures preferred 5:1 over
  // odometry, edges with a line-process weight below 0.25 pruned.
  double preference_loop_closure = 5.0;
  double edge_prune_threshold = 0.25;
  int seed = 0;  // RANSAC's seed (one per pair, derived from it: same edges for any order)
};

struct MultiwayEdge {
  int source = 0, target = 0;  // keyframe indices
  Transform T_target_source = Transform::Identity();
  double fitness = 0.0;  // ICP fitness
  bool loop = false;     // a loop edge (uncertain); false: odometry edge
  bool kept = false;     // in the graph after the optimisation (loop edges: not pruned)
};

struct MultiwayResult {
  // Pose of every keyframe in recording A's frame (T_world_keyframe; world = A's frame), valid
  // where `placed` is true: A's keyframes always, B's when a loop edge joins the two recordings.
  std::vector<Transform> T_world_keyframe;
  std::vector<bool> placed;
  std::vector<MultiwayEdge> edges;  // odometry edges, then every loop edge that passed min_fitness
  int loop_candidates = 0;          // pairs tried with FPFH + RANSAC
  // T_A_B (maps B's recording frame into A's): the chordal mean of world_from_keyframe *
  // T_rec_camera^-1 over B's placed keyframes with poses; nullopt when B is not placed or has no
  // poses.
  std::optional<Transform> T_A_B;
};

// `keyframes`: recording A's in recording order, then B's. Throws InputError when the Open3D module
// cannot be loaded, a keyframe has no points or the first keyframe is not A's.
// `progress(done, total)` is called after each loop candidate.
MultiwayResult RegisterMultiway(const std::vector<MultiwayKeyframe>& keyframes,
                                const MultiwayConfig& config = {},
                                const std::function<void(int, int)>& progress = {});

}  // namespace zeroreg
