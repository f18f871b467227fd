// EstimateNormals: exact surfaces with known normals, agreement with Open3D's
// EstimateNormals (the rule it replaces), independence of the input order, and the edge cases.
#include "estimate/normals.hpp"

#include <gtest/gtest.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace zeroreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // Sign-free: a normal and its opposite describe the same plane.
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) * 180.0 / kPi;
}

// A wavy surface z = f(x, y) on a 1 cm grid over 1.2 m x 0.9 m (ICP's 2 cm voxels see about
// a quarter of these), with its exact normals.
void WavySurface(double noise_m, std::vector<Eigen::Vector3d>* points,
                 std::vector<Eigen::Vector3d>* normals) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, noise_m);
  for (double x = 0; x < 1.2; x += 0.01) {
    for (double y = 0; y < 0.9; y += 0.01) {
      const double z = 1.5 + 0.05 * std::sin(3 * x) + 0.04 * std::cos(2 * y);
      const Eigen::Vector3d gradient(0.15 * std::cos(3 * x), -0.08 * std::sin(2 * y), 0.0);
      points->emplace_back(x, y, z + (noise_m > 0 ? noise(rng) : 0.0));
      normals->push_back(Eigen::Vector3d(-gradient.x(), -gradient.y(), 1.0).normalized());
    }
  }
}

TEST(EstimateNormals, FollowsASmoothSurface) {
  std::vector<Eigen::Vector3d> points, truth;
  WavySurface(0.0, &points, &truth);
  const std::vector<Eigen::Vector3d> normals = EstimateNormals(points, 0.03, 30);
  ASSERT_EQ(normals.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(normals[i].norm(), 1.0, 1e-12);
    EXPECT_LT(AngleDeg(normals[i], truth[i]), 1.0) << "point " << i;
  }
}

TEST(EstimateNormals, PointsOutwardOnASphereUpToSign) {
  std::vector<Eigen::Vector3d> points;
  const Eigen::Vector3d centre(0.2, -0.1, 2.0);
  for (int i = 0; i < 4000; ++i) {
    // A Fibonacci sphere of radius 0.5 m: about 2.8 cm between points.
    const double z = 1.0 - 2.0 * (i + 0.5) / 4000.0, r = std::sqrt(1.0 - z * z);
    const double phi = i * kPi * (3.0 - std::sqrt(5.0));
    points.push_back(centre + 0.5 * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z));
  }
  const std::vector<Eigen::Vector3d> normals = EstimateNormals(points, 0.09, 30);
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_LT(AngleDeg(normals[i], points[i] - centre), 2.0) << "point " << i;
  }
}

TEST(EstimateNormals, AgreesWithOpen3dOnAThinnedNoisyCloud) {
  std::vector<Eigen::Vector3d> raw, truth;
  WavySurface(0.002, &raw, &truth);  // 2 mm depth noise
  open3d::geometry::PointCloud cloud;
  cloud.points_ = raw;
  cloud = *cloud.VoxelDownSample(0.02);
  const double radius = 3 * 0.02;
  const std::vector<Eigen::Vector3d> ours = EstimateNormals(cloud.points_, radius, 30);
  cloud.EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(radius, 30));
  ASSERT_EQ(ours.size(), cloud.normals_.size());
  // The same neighbours and the same plane fit: the same normal but for rounding (a different
  // summation order), and possibly the other choice among neighbours at an exactly equal distance.
  size_t same = 0;
  for (size_t i = 0; i < ours.size(); ++i) same += AngleDeg(ours[i], cloud.normals_[i]) < 1e-3;
  EXPECT_GE(same, ours.size() * 999 / 1000) << same << " of " << ours.size();
}

TEST(EstimateNormals, DoesNotDependOnTheInputOrder) {
  std::vector<Eigen::Vector3d> points, truth;
  WavySurface(0.003, &points, &truth);
  std::vector<size_t> permutation(points.size());
  std::iota(permutation.begin(), permutation.end(), 0);
  std::shuffle(permutation.begin(), permutation.end(), std::mt19937(11));
  std::vector<Eigen::Vector3d> shuffled;
  for (size_t i : permutation) shuffled.push_back(points[i]);
  const std::vector<Eigen::Vector3d> a = EstimateNormals(points, 0.03, 30);
  const std::vector<Eigen::Vector3d> b = EstimateNormals(shuffled, 0.03, 30);
  for (size_t k = 0; k < permutation.size(); ++k) {
    EXPECT_LT(AngleDeg(a[permutation[k]], b[k]), 1e-6) << "point " << permutation[k];
  }
}

TEST(EstimateNormals, IsolatedPointsAndEmptyInput) {
  EXPECT_TRUE(EstimateNormals({}, 0.05, 30).empty());
  // Two far-apart pairs: fewer than 3 neighbours each, so no plane: (0, 0, 1) as in Open3D.
  const std::vector<Eigen::Vector3d> points = {
      {0, 0, 1}, {0.01, 0, 1}, {5, 5, 5}, {5, 5.01, 5}, {-3, 2, 1}};
  for (const Eigen::Vector3d& n : EstimateNormals(points, 0.05, 30)) {
    EXPECT_EQ(n, Eigen::Vector3d::UnitZ());
  }
  // Negative coordinates and cells across zero are found as neighbours too.
  std::vector<Eigen::Vector3d> plane;
  for (double x = -0.05; x <= 0.05; x += 0.01) {
    for (double y = -0.05; y <= 0.05; y += 0.01) plane.emplace_back(x, y, -1.0);
  }
  for (const Eigen::Vector3d& n : EstimateNormals(plane, 0.025, 30)) {
    EXPECT_LT(AngleDeg(n, Eigen::Vector3d::UnitZ()), 1e-6);
  }
}

}  // namespace
}  // namespace zeroreg
