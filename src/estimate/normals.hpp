// Surface normals of a thinned cloud, for point-to-plane ICP's target.
//
// Open3D's PointCloud::EstimateNormals (a nanoflann k-d tree, then OpenMP over the points) was
// ~8 % of a frame pair's CPU in `perf`, and its OpenMP pool competed with the pipeline's own two
// threads. ICP's clouds are thinned to one point per voxel, so the neighbours within a few voxels
// are found faster in a uniform grid whose cells are the search radius: only the 27 cells around
// a point can hold its neighbours. The rule is Open3D's hybrid search (the `max_neighbours`
// closest points within `radius`, the point itself included) and its plane fit (the eigenvector
// of the smallest eigenvalue of the neighbours' covariance).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace zeroreg {

// One unit normal per point. A point with fewer than 3 neighbours (no plane) gets (0, 0, 1), as
// in Open3D. The sign of a normal is arbitrary (point-to-plane residuals do not depend on it).
// Neighbours are ranked by squared distance, ties by index, and each normal depends only on its
// own neighbourhood: the result does not depend on the order of work or the thread count.
std::vector<Eigen::Vector3d> EstimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             double radius, int max_neighbours);

}  // namespace zeroreg
