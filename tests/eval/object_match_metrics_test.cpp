#include "eval/object_match_metrics.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace zeroreg
