#include "estimate/icp.hpp"

#include "estimate/lift.hpp"

#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <Eigen/Cholesky>

namespace zeroreg {

std::vector<Eigen::Vector3d> ScanGeometry(const Scan& scan, double voxel_m) {
  open3d::geometry::PointCloud cloud;
  cloud.points_ = ScanPoints(scan, /*stride=*/2);
  return cloud.VoxelDownSample(voxel_m)->points_;
}

IcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const Transform& initial,
                             const RefineConfig& config) {
  IcpResult result;
  result.T_target_source = initial;
  if (source.size() < 6 || target.size() < 6) return result;
  open3d::geometry::PointCloud target_cloud;
  target_cloud.points_ = target;
  // Normals from 30 neighbours within 3 voxels: each normal depends only on its neighbourhood, so
  // Open3D's parallel estimation is still deterministic.
  target_cloud.EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(3 * config.voxel_m, 30));
  open3d::geometry::KDTreeFlann tree(target_cloud);
  const double gate_sq = config.max_distance_m * config.max_distance_m;

  Transform T = initial;
  std::vector<int> index(1);
  std::vector<double> distance_sq(1);
  for (int it = 0; it < config.max_iterations; ++it) {
    // Linearised point-to-plane residual n^T (R p + t - q) with R ~ I + [w]x, x = [w; t].
    Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> Jtr = Eigen::Matrix<double, 6, 1>::Zero();
    int matched = 0;
    double sum_sq = 0;
    for (const Eigen::Vector3d& s : source) {
      const Eigen::Vector3d p = (T * s.homogeneous()).head<3>();
      if (tree.SearchKNN(p, 1, index, distance_sq) < 1 || distance_sq[0] > gate_sq) continue;
      const Eigen::Vector3d& q = target_cloud.points_[index[0]];
      const Eigen::Vector3d& n = target_cloud.normals_[index[0]];
      Eigen::Matrix<double, 6, 1> J;
      J << p.cross(n), n;
      const double r = n.dot(p - q);
      JtJ += J * J.transpose();
      Jtr += J * r;
      ++matched;
      sum_sq += distance_sq[0];
    }
    result.iterations = it + 1;
    result.fitness = static_cast<double>(matched) / source.size();
    result.rmse = matched > 0 ? std::sqrt(sum_sq / matched) : 0.0;
    if (matched < 6) break;
    const Eigen::Matrix<double, 6, 1> x = JtJ.ldlt().solve(-Jtr);
    if (!x.allFinite()) break;
    Transform step = Transform::Identity();
    const double angle = x.head<3>().norm();
    if (angle > 0) {
      step.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, x.head<3>() / angle).toRotationMatrix();
    }
    step.topRightCorner<3, 1>() = x.tail<3>();
    T = step * T;
    if (x.norm() < 1e-6) break;  // converged: sub-micrometre / sub-microradian update
  }
  result.T_target_source = T;
  return result;
}

}  // namespace zeroreg
