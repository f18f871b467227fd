#include "eval/object_match_metrics.hpp"

#include <gtest/gtest.h>

#include "rigid_motion.hpp"

namespace zeroreg {
namespace {

TEST(ObjectMatchMetrics, CountsMatchesWhoseCentroidsAgreeUnderTheGroundTruth) {
  RegistrationResult r;
  r.source_objects.resize(3);
  r.target_objects.resize(3);
  Transform gt = Transform::Identity();
  gt(0, 3) = 1.0;  // source x + 1 = target x
  r.source_objects[0].centroid = {0, 0, 2};
  r.target_objects[0].centroid = {1.1, 0, 2};  // 0.1 m off: correct
  r.source_objects[1].centroid = {1, 0, 2};
  r.target_objects[1].centroid = {2.5, 0, 2};  // 0.5 m off: wrong
  r.source_objects[2].centroid = {0, 1, 2};
  r.target_objects[2].centroid = {1, 1.29, 2};  // 0.29 m: correct at 0.3, wrong at 0.2
  r.object_matches = {{0, 0, 2.0, 10}, {1, 1, 2.0, 5}, {2, 2, 1.9, 0}};
  ObjectMatchStats s = CountCorrectObjectMatches(r, gt);
  EXPECT_EQ(s.matches, 3);
  EXPECT_EQ(s.correct, 2);
  EXPECT_EQ(CountCorrectObjectMatches(r, gt, 0.2).correct, 1);
  EXPECT_EQ(CountCorrectObjectMatches(RegistrationResult(), gt).matches, 0);
}

// The surface points of a flat object 2 m in front of a camera: the rectangle [x0, x1) x [y0, y1)
// (metres, in the camera's x-y plane) on a 2 cm grid, moved by T (camera -> scan frame).
std::vector<Eigen::Vector3d> Patch(double x0, double y0, double x1, double y1,
                                   const Transform& T = Transform::Identity()) {
  std::vector<Eigen::Vector3d> points;
  for (double x = x0; x < x1 - 1e-9; x += 0.02)
    for (double y = y0; y < y1 - 1e-9; y += 0.02)
      points.push_back((T * Eigen::Vector3d(x, y, 2.0).homogeneous()).head<3>());
  return points;
}

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

TEST(ObjectMatchMetrics, SameSurfaceFollowsTheSurfaceNotTheCentroid) {
  // The target scan's frame is the source's moved and turned: exact truth.
  const Transform truth = testing::MakeTransform(0.3, {0, 1, 0}, {0.4, -0.1, 0.5});
  // A large object (1.6 m wide) seen whole in the source and only its left fifth in the target:
  // its centroid moves by 0.6 m, its surface does not.
  const auto whole = Patch(-0.8, -0.6, 0.8, 0.6);
  const auto left_part = Patch(-0.8, -0.6, -0.48, 0.6, truth);
  const Eigen::Vector3d moved = (truth * Centroid(whole).homogeneous()).head<3>();
  EXPECT_GT((moved - Centroid(left_part)).norm(), 0.3);
  EXPECT_TRUE(SameSurface(whole, left_part, truth));
  // The part is a fifth of the whole: the test takes the larger of the two shares.
  EXPECT_TRUE(SameSurface(left_part, whole, truth.inverse()));
  // Under a wrong transform, or against another object 0.5 m to the side, no shared surface.
  EXPECT_FALSE(SameSurface(whole, left_part, Transform::Identity()));
  const auto other = Patch(1.3, -0.6, 1.7, 0.6, truth);
  EXPECT_FALSE(SameSurface(Patch(0.4, -0.6, 0.8, 0.6), other, truth));
  // Touching objects share a sliver (within 5 cm of the edge), less than a fifth of either.
  EXPECT_FALSE(SameSurface(Patch(0.4, -0.6, 0.8, 0.6), Patch(0.82, -0.6, 1.22, 0.6, truth), truth));
  EXPECT_FALSE(SameSurface({}, left_part, truth));
}

}  // namespace
}  // namespace zeroreg
