// Optional refinement of a registration by point-to-plane ICP on the scans' geometry (issue 6).
// Our own Gauss-Newton loop on Open3D's k-d tree and normals, with serial reductions, so the
// result is a function of the input only (Open3D's ICP sums in parallel threads).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct IcpResult {
  Transform T_target_source = Transform::Identity();
  double fitness = 0.0;  // fraction of source points with a target point within the distance
  double rmse = 0.0;     // metres, over those points
  int iterations = 0;
};

// Geometry of a scan for ICP: its point cloud if it has one, else the back-projected depth of its
// views, voxel-downsampled to `voxel_m`.
std::vector<Eigen::Vector3d> ScanGeometry(const Scan& scan, double voxel_m);

// Point-to-plane ICP from `initial`, with correspondences within `config.max_distance_m`.
IcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const Transform& initial,
                             const RefineConfig& config);

}  // namespace zeroreg
