#include "objects/scene_objects.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "estimate/lift.hpp"

namespace zeroreg {
namespace {

// Points filling an axis-aligned box, on a regular 1 cm grid.
std::vector<Eigen::Vector3d> BoxPoints(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3d> points;
  for (double x = lo.x(); x <= hi.x(); x += 0.01)
    for (double y = lo.y(); y <= hi.y(); y += 0.01)
      for (double z = lo.z(); z <= hi.z(); z += 0.01) points.emplace_back(x, y, z);
  return points;
}

ObjectObservation Observation(int view, const std::string& label, float score,
                              const std::vector<Eigen::Vector3d>& points) {
  ObjectObservation o;
  o.view = view;
  o.detection.label = label;
  o.detection.score = score;
  o.points = points;
  return o;
}

TEST(SceneObjects, VoxelOverlapOfIdenticalDisjointAndHalfOverlappingSets) {
  const auto a = BoxPoints({0, 0, 0}, {0.19, 0.19, 0.19});
  const auto far = BoxPoints({1, 1, 1}, {1.19, 1.19, 1.19});
  const auto half = BoxPoints({0.1, 0, 0}, {0.29, 0.19, 0.19});
  EXPECT_DOUBLE_EQ(VoxelOverlap(a, a, 0.05), 1.0);
  EXPECT_DOUBLE_EQ(VoxelOverlap(a, far, 0.05), 0.0);
  EXPECT_NEAR(VoxelOverlap(a, half, 0.05), 0.5, 1e-9);
}

TEST(SceneObjects, AssociatesTheSameObjectAcrossViewsAndDropsSingleViewObjects) {
  const auto chair = BoxPoints({0, 0, 2}, {0.4, 0.8, 2.4});
  const auto chair_seen_from_1 = BoxPoints({0.05, 0, 2}, {0.4, 0.8, 2.4});  // partly occluded
  const auto table = BoxPoints({1, 0.5, 2}, {2, 0.6, 3});
  const auto cup = BoxPoints({1.2, 0.4, 2.2}, {1.28, 0.5, 2.28});
  const std::vector<ObjectObservation> observations = {
      Observation(0, "chair", 0.7f, chair),
      Observation(0, "dining table", 0.8f, table),
      Observation(1, "chair", 0.9f, chair_seen_from_1),
      Observation(1, "dining table", 0.6f, table),
      Observation(2, "cup", 0.6f, cup),      // seen in one view only
      Observation(2, "couch", 0.5f, chair),  // same place, incompatible label: not the chair
  };
  const auto objects = AssociateObservations(observations, 3, ObjectsConfig());
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].label, "chair");
  EXPECT_FLOAT_EQ(objects[0].score, 0.9f);
  EXPECT_EQ(objects[0].views, (std::vector<int>{0, 1}));
  EXPECT_NEAR(objects[0].centroid.x(), 0.2, 0.02);
  EXPECT_NEAR(objects[0].centroid.z(), 2.2, 0.02);
  EXPECT_EQ(objects[1].label, "dining table");
  EXPECT_EQ(objects[1].observations, (std::vector<int>{1, 3}));
}

TEST(SceneObjects, NeverMergesTwoObservationsOfTheSameView) {
  // View 0 sees two chairs side by side; view 1 has one wide "chair" box over both. Overlap alone
  // would chain all three into one object.
  const auto chair_a = BoxPoints({0, 0, 2}, {0.4, 0.8, 2.4});
  const auto chair_b = BoxPoints({0.5, 0, 2}, {0.9, 0.8, 2.4});
  const auto both = BoxPoints({0, 0, 2}, {0.9, 0.8, 2.4});
  const auto objects = AssociateObservations(
      {Observation(0, "chair", 0.8f, chair_a), Observation(0, "chair", 0.7f, chair_b),
       Observation(1, "chair", 0.6f, both)},
      2, ObjectsConfig());
  ASSERT_EQ(objects.size(), 1u);  // chair A with the wide box; chair B alone (one view) is dropped
  EXPECT_EQ(objects[0].observations, (std::vector<int>{0, 2}));
  EXPECT_EQ(objects[0].views, (std::vector<int>{0, 1}));
}

TEST(SceneObjects, SingleViewScanKeepsEveryObject) {
  const std::vector<ObjectObservation> observations = {
      Observation(0, "cup", 0.6f, BoxPoints({0, 0, 1}, {0.1, 0.1, 1.1})),
      Observation(0, "cup", 0.5f, BoxPoints({0.5, 0, 1}, {0.6, 0.1, 1.1}))};
  const auto objects = AssociateObservations(observations, 1, ObjectsConfig());
  EXPECT_EQ(objects.size(), 2u);
}

TEST(SceneObjects, SemanticSynonymsAssociateAndFeaturesAreAveraged) {
  auto a = Observation(0, "couch", 0.6f, BoxPoints({0, 0, 1}, {0.5, 0.3, 1.5}));
  auto b = Observation(1, "sofa", 0.7f, BoxPoints({0, 0, 1}, {0.5, 0.3, 1.5}));
  a.semantic = Eigen::Vector2d(1.0, 0.0);
  b.semantic = Eigen::Vector2d(0.995, 0.0998);  // cos ~ 0.995: synonyms
  const auto objects = AssociateObservations({a, b}, 2, ObjectsConfig());
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].label, "sofa");
  EXPECT_NEAR(objects[0].semantic(0), 0.9975, 1e-9);
}

TEST(SceneObjects, LiftMaskSkipsInvalidDepthAndEdges) {
  View view;
  view.intrinsics = {100, 100, 32, 24, 64, 48};
  view.color = cv::Mat(48, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  view.depth = cv::Mat(48, 64, CV_32F, cv::Scalar(2.0f));
  view.depth(cv::Rect(0, 0, 16, 48)).setTo(4.0f);  // left quarter: a surface 2 m behind (an edge)
  view.depth(cv::Rect(40, 0, 1, 48)).setTo(0.0f);  // a thin hole (HoloLens-style): not an edge
  cv::Mat mask(48, 64, CV_8U, cv::Scalar(0));
  mask(cv::Rect(16, 0, 48, 48)).setTo(255);  // the near surface only
  ObjectsConfig objects;
  objects.pixel_stride = 1;
  const auto points = LiftMask(view, mask, objects, ViewLift());
  ASSERT_FALSE(points.empty());
  const int radius = LiftConfig().depth_edge_radius_px;
  bool beside_hole = false;
  for (const auto& p : points) {
    EXPECT_DOUBLE_EQ(p.z(), 2.0);
    const double u = p.x() * 100 / 2.0 + 32;  // x = (u - cx) z / fx
    // Every lifted pixel lies at least `radius` px right of the depth jump ...
    EXPECT_GE(u, 16 + radius - 1e-9);
    EXPECT_NE(u, 40.0);  // ... and none is the hole itself,
    beside_hole |= std::abs(u - 41) < 1e-9;
  }
  EXPECT_TRUE(beside_hole) << "pixels next to a hole are lifted";
}

// The default grid (objects.pixel_stride = 0) takes about the same number of points from an
// object's mask whatever the image size, so objects.min_points means the same share of a view.
TEST(SceneObjects, LiftMaskPointCountFollowsTheImageSize) {
  auto lifted = [](int width, int height, int stride) {
    View view;
    view.intrinsics = {width * 0.9,        width * 0.9, (width - 1) / 2.0,
                       (height - 1) / 2.0, width,       height};
    view.color = cv::Mat(height, width, CV_8UC3, cv::Scalar(0, 0, 0));
    view.depth = cv::Mat(height, width, CV_32F, cv::Scalar(2.0f));
    cv::Mat mask(height, width, CV_8U, cv::Scalar(0));
    mask(cv::Rect(width / 4, height / 4, width / 2, height / 2)).setTo(255);  // a quarter of it
    ObjectsConfig objects;
    objects.pixel_stride = stride;
    return static_cast<double>(LiftMask(view, mask, objects, ViewLift()).size());
  };
  const double at_640 = lifted(640, 480, 0);
  EXPECT_EQ(at_640, lifted(640, 480, 4));               // auto = 4 at 640 px wide, as before
  EXPECT_EQ(lifted(540, 360, 0), lifted(540, 360, 4));  // and at HoloLens' 540
  EXPECT_NEAR(lifted(1280, 960, 0) / at_640, 1.0, 0.02);
  EXPECT_NEAR(lifted(320, 240, 0) / at_640, 1.0, 0.02);
  EXPECT_NEAR(lifted(1280, 960, 4) / at_640, 4.0, 0.1);
}

}  // namespace
}  // namespace zeroreg
