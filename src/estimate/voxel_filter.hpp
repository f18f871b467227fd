// Voxel down-sampling: the points of each occupied voxel replaced by their mean, as ICP's
// resolutions need it (src/estimate/icp.cpp).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace zeroreg {

struct VoxelMeans {
  std::vector<Eigen::Vector3d> points;  // one mean per occupied voxel
  std::vector<double> values;           // mean of the per-point values (empty when none given)
};

// The grid's voxels are voxel_m wide, anchored half a voxel below the cloud's smallest
// coordinates; `values` (empty, or one per point: ICP's depth readings) are averaged alongside.
// Output order: that of Open3D 0.16's PointCloud::VoxelDownSample (its hash map's iteration
// order, reproduced by the same container and hash), so that ICP, which sums in point order, gives
// bit for bit the results it gave through Open3D (tested against Open3D: VoxelFilter.*).
// Points with a coordinate beyond the int range in voxels would not fit the grid: voxel_m must
// be > 0 and the cloud's extent / voxel_m below 2^31 (IcpGeometry's stages are centimetres
// over metres).
VoxelMeans VoxelDownSample(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& values, double voxel_m);

}  // namespace zeroreg
