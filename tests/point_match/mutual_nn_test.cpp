#include <gtest/gtest.h>

#include "point_match/descriptor_matcher.hpp"

namespace zeroreg {
namespace {

TEST(MutualNearestNeighbour, KeepsOnlyMutualPairsAboveThreshold) {
  Eigen::MatrixXf a(3, 2), b(3, 2);
  a << 1, 0, 0, 1, 0.7071f, 0.7071f;
  b << 0, 1, 1, 0, -1, 0;  // a0<->b1, a1<->b0; a2's best is b0 or b1, neither picks it back
  const auto matches = MutualNearestNeighbourMatcher(0.5).Match(a, b, 1);
  ASSERT_EQ(matches.size(), 2u);
  EXPECT_EQ(matches[0].source, 0);
  EXPECT_EQ(matches[0].target, 1);
  EXPECT_EQ(matches[1].source, 1);
  EXPECT_EQ(matches[1].target, 0);
  EXPECT_FLOAT_EQ(matches[0].score, 1.0f);
  EXPECT_TRUE(MutualNearestNeighbourMatcher(1.1).Match(a, b, 1).empty());
  EXPECT_TRUE(MutualNearestNeighbourMatcher(0.5).Match(Eigen::MatrixXf(0, 2), b, 1).empty());
}

}  // namespace
}  // namespace zeroreg
