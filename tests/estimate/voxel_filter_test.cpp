// VoxelDownSample (ICP's resolutions without Open3D, docs/SPEED.md "Start-up"): the same means, in
// the same order, bit for bit, as Open3D 0.16's PointCloud::VoxelDownSample with the values riding
// in its colour channel (how ICP used it before), on synthetic and real clouds.
#include "estimate/voxel_filter.hpp"

#include <gtest/gtest.h>
#include <open3d/geometry/PointCloud.h>

#include <random>
#include <stdexcept>

#include "estimate/lift.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

void ExpectSameAsOpen3d(const std::vector<Eigen::Vector3d>& points,
                        const std::vector<double>& values, double voxel_m) {
  open3d::geometry::PointCloud cloud;
  cloud.points_ = points;
  for (double v : values) cloud.colors_.emplace_back(v, 0.0, 0.0);
  const auto reference = cloud.VoxelDownSample(voxel_m);
  const VoxelMeans ours = VoxelDownSample(points, values, voxel_m);
  ASSERT_EQ(ours.points.size(), reference->points_.size());
  ASSERT_EQ(ours.values.size(), values.empty() ? 0u : reference->colors_.size());
  for (size_t i = 0; i < ours.points.size(); ++i) {
    // Exact: the same sums in the same order, the same voxel in the same place.
    ASSERT_EQ(ours.points[i], reference->points_[i]) << "voxel " << i;
    if (!values.empty()) {
      ASSERT_EQ(ours.values[i], reference->colors_[i].x()) << "voxel " << i;
    }
  }
}

TEST(VoxelFilter, GivesOpen3dsMeansInOpen3dsOrderOnRandomClouds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.5, 2.5), reading(0.5, 4.0);
  for (double voxel_m : {0.01, 0.02, 0.05, 0.3}) {
    SCOPED_TRACE(voxel_m);
    std::vector<Eigen::Vector3d> points(20000);
    std::vector<double> values(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      points[i] = {coordinate(rng), coordinate(rng), coordinate(rng)};
      values[i] = reading(rng);
    }
    ExpectSameAsOpen3d(points, values, voxel_m);
    ExpectSameAsOpen3d(points, {}, voxel_m);
  }
}

TEST(VoxelFilter, GivesOpen3dsMeansInOpen3dsOrderOnRealFrames) {
  const auto dataset = OpenDataset(testing::RedkitchenDir());
  for (int frame : {0, 20}) {
    Scan scan;
    scan.views.push_back(dataset->LoadFrame(frame));
    std::vector<double> depth;
    const std::vector<Eigen::Vector3d> points = ScanPoints(scan, PixelGrid{2}, 0.0, 1e9, &depth);
    ASSERT_GT(points.size(), 10000u);
    for (double voxel_m : {0.02, 0.04, 0.08}) {
      SCOPED_TRACE(std::to_string(frame) + " @ " + std::to_string(voxel_m));
      ExpectSameAsOpen3d(points, depth, voxel_m);
    }
  }
}

TEST(VoxelFilter, AveragesEachVoxelAndRefusesBadInput) {
  // Two points share the voxel at the origin, one is alone far away.
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0.02, 0.04, 0}, {1, 1, 1}};
  const VoxelMeans means = VoxelDownSample(points, {1.0, 3.0, 5.0}, 0.1);
  ASSERT_EQ(means.points.size(), 2u);
  bool found_pair = false, found_single = false;
  for (size_t i = 0; i < means.points.size(); ++i) {
    if ((means.points[i] - Eigen::Vector3d(0.01, 0.02, 0)).norm() < 1e-12) {
      found_pair = true;
      EXPECT_DOUBLE_EQ(means.values[i], 2.0);
    }
    if ((means.points[i] - Eigen::Vector3d(1, 1, 1)).norm() < 1e-12) {
      found_single = true;
      EXPECT_DOUBLE_EQ(means.values[i], 5.0);
    }
  }
  EXPECT_TRUE(found_pair);
  EXPECT_TRUE(found_single);
  EXPECT_TRUE(VoxelDownSample({}, {}, 0.1).points.empty());
  EXPECT_THROW(VoxelDownSample(points, {}, 0.0), std::invalid_argument);
  EXPECT_THROW(VoxelDownSample(points, {1.0}, 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace zeroreg
