#include "objects/proposals.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "eval/metrics.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

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
  TopUpWithProposals(view, objects, ViewLift(), &found);
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
  TopUpWithProposals(view, objects, ViewLift(), &found);
  ASSERT_EQ(found.size(), 2u);  // the detection and the right box only
  EXPECT_EQ(found[0].detection.label, "box");
  EXPECT_GT(found[1].detection.box.x, 160);

  objects.proposals_below = 1;  // one usable detection is enough: nothing added
  found = {detected};
  TopUpWithProposals(view, objects, ViewLift(), &found);
  EXPECT_EQ(found.size(), 1u);
  objects.proposals_below = 0;  // off
  found.clear();
  TopUpWithProposals(view, objects, ViewLift(), &found);
  EXPECT_TRUE(found.empty());
}

// On real frames with every view topped up (redkitchen 858 -> 490, redkitchen-cross): proposals
// become objects of the scans, labelled kProposalLabel, and the registration stays right. Their
// label is not looked up in the CLIP tables, so the run prints no "is in no CLIP table" warning.
TEST(Proposals, RealFramesToppedUpGiveUnlabelledObjectsWithoutAWarning) {
  const std::string dir = testing::SharedDir() + "/data/7scenes-redkitchen@";
  const Scan source = LoadScan(dir + "858"), target = LoadScan(dir + "490");
  const Transform gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
  PipelineConfig config;
  config.objects.proposals_below = 20;
  const Pipeline pipeline(config);
  ::testing::internal::CaptureStderr();
  const RegistrationResult r = pipeline.Register(source, target);
  const std::string printed = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed.find("is in no CLIP table"), std::string::npos) << printed;
  const auto unlabelled = [](const std::vector<ObjectSummary>& objects) {
    return std::count_if(objects.begin(), objects.end(),
                         [](const ObjectSummary& o) { return o.label == kProposalLabel; });
  };
  EXPECT_GT(unlabelled(r.source_objects), 0);
  EXPECT_GT(unlabelled(r.target_objects), 0);
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.30);
}

}  // namespace
}  // namespace zeroreg
