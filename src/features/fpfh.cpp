#include "features/fpfh.hpp"

#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Feature.h>

#include <cmath>

namespace zeroreg {

FpfhCloud ComputeFpfh(const std::vector<Eigen::Vector3d>& points, const FpfhParams& p) {
  open3d::geometry::PointCloud full;
  full.points_ = points;
  FpfhCloud out;
  out.cloud = full.VoxelDownSample(p.voxel_m);
  out.cloud->EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(
      p.normal_radius_voxels * p.voxel_m, p.normal_max_nn));
  out.feature = open3d::pipelines::registration::ComputeFPFHFeature(
      *out.cloud, open3d::geometry::KDTreeSearchParamHybrid(p.feature_radius_voxels * p.voxel_m,
                                                            p.feature_max_nn));
  return out;
}

std::vector<FeaturePair> MutualFeatureMatches(const FpfhCloud& source, const FpfhCloud& target) {
  std::vector<FeaturePair> out;
  const Eigen::Index ns = source.feature->data_.cols(), nt = target.feature->data_.cols();
  if (ns < 2 || nt < 2) return out;
  const open3d::geometry::KDTreeFlann target_tree(*target.feature);
  const open3d::geometry::KDTreeFlann source_tree(*source.feature);
  std::vector<int> index(2);
  std::vector<double> distance2(2);
  for (Eigen::Index s = 0; s < ns; ++s) {
    const Eigen::VectorXd query = source.feature->data_.col(s);
    if (target_tree.SearchKNN(query, 2, index, distance2) < 2) continue;
    const int t = index[0];
    const double d1 = std::sqrt(distance2[0]), d2 = std::sqrt(distance2[1]);
    std::vector<int> back(1);
    std::vector<double> back_distance2(1);
    const Eigen::VectorXd reverse = target.feature->data_.col(t);
    if (source_tree.SearchKNN(reverse, 1, back, back_distance2) < 1) continue;
    if (back[0] != static_cast<int>(s)) continue;
    FeaturePair pair;
    pair.source = static_cast<int>(s);
    pair.target = t;
    pair.score = d2 > 0 ? static_cast<float>(1.0 - d1 / d2) : 0.0f;
    out.push_back(pair);
  }
  return out;
}

}  // namespace zeroreg
