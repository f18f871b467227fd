#include "object_match/surface_overlap.hpp"

#include <gtest/gtest.h>

#include "rigid_motion.hpp"

namespace zeroreg {
namespace {

// A flat square of side `size` m at depth 2 m, points on a 2 cm grid, starting at x = x0.
std::vector<Eigen::Vector3d> Square(double x0, double size) {
  std::vector<Eigen::Vector3d> points;
  for (double x = 0; x < size - 1e-9; x += 0.02)
    for (double y = 0; y < size - 1e-9; y += 0.02) points.emplace_back(x0 + x, y, 2.0);
  return points;
}

TEST(SurfaceOverlap, TheSharedShareOfEitherSurfaceDecides) {
  const Transform truth = testing::MakeTransform(0.5, {1, 0, 0}, {0.2, 0.3, -0.1});
  std::vector<Eigen::Vector3d> whole = Square(0, 1.0), moved_part;
  for (const Eigen::Vector3d& p : Square(0, 0.3)) moved_part.push_back(testing::Apply(truth, p));
  // The part (9 % of the whole) lies entirely on the whole: either direction counts.
  EXPECT_TRUE(SurfacesCoincide(whole, moved_part, truth, 0.05, 0.2));
  // But not under another motion, nor if a fifth must be shared and the radius is too small to
  // bridge a 2 cm offset.
  EXPECT_FALSE(SurfacesCoincide(whole, moved_part, Transform::Identity(), 0.05, 0.2));
  std::vector<Eigen::Vector3d> shifted;
  for (const Eigen::Vector3d& p : whole) shifted.push_back(p + Eigen::Vector3d(0, 0, 0.02));
  EXPECT_TRUE(SurfacesCoincide(whole, shifted, Transform::Identity(), 0.025, 0.2));
  EXPECT_FALSE(SurfacesCoincide(whole, shifted, Transform::Identity(), 0.015, 0.2));
  EXPECT_FALSE(SurfacesCoincide({}, whole, Transform::Identity(), 0.05, 0.2));
  EXPECT_FALSE(SurfacesCoincide(whole, {}, Transform::Identity(), 0.05, 0.2));
}

}  // namespace
}  // namespace zeroreg
