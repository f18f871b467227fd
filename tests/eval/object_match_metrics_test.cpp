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

// A 640x480 view of a wall 2 m in front of the camera (fx = fy = 500: 1 px = 4 mm there), posed
// by T_scan_camera.
Scan Wall(const Transform& T_scan_camera) {
  View v;
  v.depth = cv::Mat1f(480, 640, 2.0f);
  v.color = cv::Mat3b(480, 640, cv::Vec3b(128, 128, 128));
  v.intrinsics = {500, 500, 320, 240, 640, 480};
  v.T_scan_camera = T_scan_camera;
  Scan scan;
  scan.views = {v};
  return scan;
}

// An object seen in view 0 whose mask outline is the rectangle [x0, x1] x [y0, y1] (pixels).
ObjectSummary Rectangle(int x0, int y0, int x1, int y1) {
  ObjectSummary o;
  ObjectView v;
  v.outline = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  o.views = {v};
  return o;
}

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

TEST(ObjectMatchMetrics, ObjectSurfaceLiftsTheMaskOnThePixelGrid) {
  const Scan wall = Wall(Transform::Identity());
  const std::vector<Eigen::Vector3d> surface = ObjectSurface(wall, Rectangle(100, 100, 199, 199));
  // Every 4th pixel of a 100 x 100 px mask (PixelGrid at 640 px), all at depth 2 m.
  EXPECT_EQ(surface.size(), 25u * 25u);
  for (const Eigen::Vector3d& p : surface) EXPECT_DOUBLE_EQ(p.z(), 2.0);
  EXPECT_NEAR(Centroid(surface).x(), (148.0 - 320.0) * 2.0 / 500.0, 1e-9);
  // Nothing to lift: no outline, a view the scan does not have.
  EXPECT_TRUE(ObjectSurface(wall, ObjectSummary()).empty());
  ObjectSummary elsewhere = Rectangle(100, 100, 199, 199);
  elsewhere.views[0].view = 3;
  EXPECT_TRUE(ObjectSurface(wall, elsewhere).empty());
}

TEST(ObjectMatchMetrics, SameSurfaceFollowsTheSurfaceNotTheCentroid) {
  // The target scan sees the same wall from a camera moved and turned: exact truth.
  const Transform truth = testing::MakeTransform(0.3, {0, 1, 0}, {0.4, -0.1, 0.5});
  const Scan source = Wall(Transform::Identity()), target = Wall(truth);
  // A large object (1.6 m wide) seen whole in the source and only its left third in the target:
  // its centroid moves by 0.5 m, its surface does not.
  const auto whole = ObjectSurface(source, Rectangle(100, 100, 499, 399));
  const auto left_part = ObjectSurface(target, Rectangle(100, 100, 249, 399));
  const Eigen::Vector3d moved = (truth * Centroid(whole).homogeneous()).head<3>();
  EXPECT_GT((moved - Centroid(left_part)).norm(), 0.3);
  EXPECT_TRUE(SameSurface(whole, left_part, truth));
  // Under a wrong transform, or against another object 0.8 m to the side, no shared surface.
  EXPECT_FALSE(SameSurface(whole, left_part, Transform::Identity()));
  const auto other = ObjectSurface(target, Rectangle(500, 100, 599, 199));
  EXPECT_FALSE(SameSurface(ObjectSurface(source, Rectangle(100, 100, 199, 199)), other, truth));
  EXPECT_FALSE(SameSurface({}, left_part, truth));
}

}  // namespace
}  // namespace zeroreg
