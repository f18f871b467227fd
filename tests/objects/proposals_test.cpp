#include "objects/proposals.hpp"

#include <gtest/gtest.h>

namespace zeroreg {
namespace {

// A 320x240 view of a wall at 3 m with two boxes standing 1.5 m in front of it.
View TwoBoxesBeforeAWall() {
  View view;
  view.intrinsics = {300, 300, 160, 120, 320, 240};
  view.color = cv::Mat(240, 320, CV_8UC3, cv::Scalar(90, 120, 150));
  view.depth = cv::Mat(240, 320, CV_32F, cv::Scalar(3.0f));
  view.depth(cv::Rect(40, 60, 80, 80)).setTo(1.5f);
  view.depth(cv::Rect(200, 80, 80, 80)).setTo(1.5f);
  return view;
}

TEST(Proposals, TopUpAddsTheDepthRegionsToAViewWithoutDetections) {
  const View view = TwoBoxesBeforeAWall();
  ObjectsConfig objects;
  objects.proposals_below = 2;
  std::vector<ObjectObservation> found;
  TopUpWithProposals(view, objects, LiftConfig(), &found);
  // Both boxes, not the wall (more than a quarter of the image).
  ASSERT_EQ(found.size(), 2u);
  for (const ObjectObservation& o : found) {
    EXPECT_EQ(o.detection.label, "object");
    EXPECT_NEAR(o.detection.box.height, 80, 8);
  }
}

TEST(Proposals, TopUpSkipsRegionsADetectionCoversAndViewsWithEnoughDetections) {
  const View view = TwoBoxesBeforeAWall();
  ObjectObservation detected;
  detected.detection.label = "box";
  detected.mask = cv::Mat(240, 320, CV_8U, cv::Scalar(0));
  detected.mask(cv::Rect(36, 56, 88, 88)).setTo(255);  // the left box, detected and segmented
  ObjectsConfig objects;
  objects.proposals_below = 2;
  std::vector<ObjectObservation> found = {detected};
  TopUpWithProposals(view, objects, LiftConfig(), &found);
  ASSERT_EQ(found.size(), 2u);  // the detection and the right box only
  EXPECT_EQ(found[0].detection.label, "box");
  EXPECT_GT(found[1].detection.box.x, 160);

  objects.proposals_below = 1;  // one usable detection is enough: nothing added
  found = {detected};
  TopUpWithProposals(view, objects, LiftConfig(), &found);
  EXPECT_EQ(found.size(), 1u);
  objects.proposals_below = 0;  // off
  found.clear();
  TopUpWithProposals(view, objects, LiftConfig(), &found);
  EXPECT_TRUE(found.empty());
}

}  // namespace
}  // namespace zeroreg
