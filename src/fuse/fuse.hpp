// 3DMatch-style fragments: TSDF fusion of N posed RGB-D frames (Open3D), expressed in the camera
// frame of the first frame, keeping k chosen views so that the fragment is a Scan with views.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "zeroreg/io.hpp"

namespace zeroreg {

struct FuseConfig {
  // Accepted voxel sizes. TSDF memory grows with 1 / voxel^2 over the scanned surface: 1 cm takes
  // a few hundred MB for a 3DMatch fragment, and 0.1 mm grew without bound. The smallest size can
  // be lowered with $ZEROREG_MIN_FUSE_VOXEL_M (docs/FORMATS.md, "Limits").
  static constexpr double kMinVoxelLengthM = 0.002;
  static constexpr double kMaxVoxelLengthM = 0.2;
  double voxel_length_m = 0.01;  // TSDF voxel; 3DMatch-scale detail at indoor ranges
  double sdf_trunc_m = 0.04;     // truncation: 4 voxels
  double max_depth_m = 6.0;      // depth beyond this is not integrated
  double output_voxel_m = 0.01;  // the stored cloud is voxel-downsampled to this
  int num_views = 3;             // kept views: evenly spaced, first and last included
};

// Smallest accepted voxel_length_m: $ZEROREG_MIN_FUSE_VOXEL_M when set, else kMinVoxelLengthM.
double MinFuseVoxelLengthM();

// Throws InputError naming the CLI option (--voxel, --views) unless every value is usable.
void CheckFuseConfig(const FuseConfig& config);

// Frame ids of the kept views: k evenly spaced ids from `frame_ids`, first and last included
// (k = 3: first, middle, last). k >= number of frames keeps all.
std::vector<int> ChooseViewFrames(const std::vector<int>& frame_ids, int num_views);

// Fuses `frame_ids` of `dataset` into `out_dir` (scan.json, cloud.ply, view images, fuse.json).
// If out_dir already holds a fragment made from the same dataset, frames and config, it is reused
// (returns false); otherwise it is (re)built (returns true). Every frame needs a ground-truth pose.
// `progress(done, total)` is called after each integrated frame when given.
bool FuseFragment(const Dataset& dataset, const std::vector<int>& frame_ids,
                  const FuseConfig& config, const std::string& out_dir,
                  const std::function<void(int, int)>& progress = nullptr);

}  // namespace zeroreg
