// Optional refinement of a registration by coarse-to-fine point-to-plane ICP on the scans'
// geometry (issue 6). Our own Gauss-Newton loop on Open3D's k-d tree and normals, with serial
// reductions, so the result is a function of the input only (Open3D's ICP sums in parallel
// threads).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct IcpResult {
  Transform T_target_source = Transform::Identity();
  double fitness = 0.0;  // last stage: fraction of source points with a target point in the gate
  double rmse = 0.0;     // metres, over those points
  int iterations = 0;    // over all stages
};

// One ICP stage: points thinned to one per voxel_m cube, closest-point pairs farther apart than
// max_distance_m ignored, at most `iterations` Gauss-Newton steps.
struct IcpStage {
  double voxel_m = 0.02;
  double max_distance_m = 0.05;
  int iterations = 30;
  // Total weight of the IcpAnchors in this stage's gate relative to all its closest-point pairs
  // (0 = not used).
  double anchor_weight = 0.0;
  // anchor_weight scales the inverse-variance weight (RefineConfig::anchor_inverse_variance).
  bool inverse_variance = false;
};

// Image correspondences that ICP must keep agreeing with (the estimate's RANSAC inliers): each pair
// adds the 3D residual T * source - target to the fit, gated like the closest-point pairs of each
// stage. They anchor the motions the geometry leaves weak (sliding along a floor or a wall), where
// plain ICP follows the bias of pairs at the fringe of the overlap (issue 10).
struct IcpAnchors {
  std::vector<Eigen::Vector3d> source, target;  // parallel
};

// The coarse, fine and final stages of RefineConfig, in order.
std::vector<IcpStage> IcpSchedule(const RefineConfig& config);

// Point-to-plane ICP from `initial` through `stages`, on raw (not yet thinned) points in the
// source and target frames.
IcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const Transform& initial,
                             const std::vector<IcpStage>& stages,
                             const IcpAnchors& anchors = IcpAnchors());

}  // namespace zeroreg
