// FPFH geometric descriptors of a point cloud (Rusu et al., ICRA 2009), through Open3D (in the
// module loaded on first use, src/open3d_module/): voxel down-sampling, normals, then one 33-bin
// histogram per kept point. Shared by the FPFH + RANSAC baseline (src/eval/methods.cpp) and the
// pipeline's geometry hypothesis (src/pipeline/hypotheses.cpp).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "open3d_module/open3d_module.hpp"

namespace zeroreg {

// The parameters (radii in voxels) and the result: points and 33 x N features.
using FpfhParams = open3d_module::FpfhParams;
using FpfhCloud = open3d_module::FpfhCloud;

// Throws InputError when the Open3D module cannot be loaded (open3d_module::Module).
FpfhCloud ComputeFpfh(const std::vector<Eigen::Vector3d>& points, const FpfhParams& params);

// Mutual nearest neighbours in FPFH space (Euclidean): (source index, target index, score) with
// score = 1 - d1 / d2, Lowe's ratio of the best to the second-best feature distance in the source
// -> target direction (0 = ambiguous, 1 = distinctive). Ties go to the lower index; the result
// is the same for any `threads`.
struct FeaturePair {
  int source = 0, target = 0;
  float score = 0.0f;
};
std::vector<FeaturePair> MutualFeatureMatches(const FpfhCloud& source, const FpfhCloud& target,
                                              int threads = 1);

}  // namespace zeroreg
