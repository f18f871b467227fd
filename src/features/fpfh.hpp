// FPFH geometric descriptors of a point cloud (Rusu et al., ICRA 2009), through Open3D (in the
// module loaded on first use, src/open3d_module/): voxel down-sampling, normals, then one 33-bin
// histogram per kept point. Shared by the FPFH + RANSAC
// baseline (src/eval/methods.cpp) and the pipeline's geometry hypothesis (issue 12,
// src/pipeline/hypotheses.cpp).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace zeroreg {

struct FpfhParams {
  double voxel_m = 0.05;               // voxel down-sampling
  double normal_radius_voxels = 2.0;   // normals: hybrid search radius, in voxels
  int normal_max_nn = 30;              // normals: at most this many neighbours
  double feature_radius_voxels = 5.0;  // FPFH: hybrid search radius, in voxels
  int feature_max_nn = 100;            // FPFH: at most this many neighbours
};

struct FpfhCloud {
  std::vector<Eigen::Vector3d> points;  // the down-sampled points
  Eigen::MatrixXd features;             // 33 x points.size(), a column per point
};

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
