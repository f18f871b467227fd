#include "object_match/result_support.hpp"

#include <gtest/gtest.h>

#include "rigid_motion.hpp"

namespace zeroreg {
namespace {

using testing::Apply;
using testing::MakeTransform;

const Transform kScene = MakeTransform(0.4, {0, 1, 0.2}, {0.3, -0.1, 0.6});

// A 0.3 m square patch of surface at `corner` (2 cm grid), in the source frame.
std::vector<Eigen::Vector3d> Patch(const Eigen::Vector3d& corner) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) points.push_back(corner + Eigen::Vector3d(0.02 * i, 0.02 * j, 0));
  return points;
}

std::vector<Eigen::Vector3d> Moved(const std::vector<Eigen::Vector3d>& points, const Transform& T) {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : points) out.push_back(Apply(T, p));
  return out;
}

// n point matches of `points` whose partners are where `truth` puts them.
MatchMotion Matches(const std::vector<Eigen::Vector3d>& points, const Transform& truth, int n) {
  MatchMotion m;
  for (int i = 0; i < n; ++i) {
    m.source.push_back(points[static_cast<size_t>(i * 7)]);
    m.target.push_back(Apply(truth, points[static_cast<size_t>(i * 7)]));
  }
  return m;
}

TEST(ResultSupport, PointMatchesOrSurfacesDecide) {
  const std::vector<Eigen::Vector3d> cup = Patch({0, 0, 2});
  const std::vector<Eigen::Vector3d> cup_in_target = Moved(cup, kScene);
  // Another object of the same class 1 m away in the target.
  const Transform elsewhere = MakeTransform(0.0, {0, 0, 1}, {1.0, 0, 0}) * kScene;
  const std::vector<Eigen::Vector3d> other_in_target = Moved(cup, elsewhere);
  const double threshold = 0.05;

  // A right match: its point matches and its surfaces agree with the scene's motion.
  EXPECT_TRUE(
      TransformSupportsMatch(kScene, Matches(cup, kScene, 10), cup, cup_in_target, threshold));
  // The other object: point matches consistent with another motion, surfaces 1 m apart.
  EXPECT_FALSE(
      TransformSupportsMatch(kScene, Matches(cup, elsewhere, 10), cup, other_in_target, threshold));
  // The right object whose point matches are wrong: its surfaces still coincide.
  EXPECT_TRUE(
      TransformSupportsMatch(kScene, Matches(cup, elsewhere, 10), cup, cup_in_target, threshold));
  // Point matches alone suffice (e.g. masks covering different parts of the object), from 4.
  EXPECT_TRUE(
      TransformSupportsMatch(kScene, Matches(cup, kScene, 4), cup, other_in_target, threshold));
  MatchMotion three_of_ten = Matches(cup, elsewhere, 10);
  for (int i = 0; i < 3; ++i)
    three_of_ten.target[static_cast<size_t>(i)] =
        Apply(kScene, three_of_ten.source[static_cast<size_t>(i)]);
  EXPECT_FALSE(TransformSupportsMatch(kScene, three_of_ten, cup, other_in_target, threshold));
  // Fewer than 4 point matches: all of them must be carried; none at all is not judged.
  EXPECT_TRUE(
      TransformSupportsMatch(kScene, Matches(cup, kScene, 2), cup, other_in_target, threshold));
  EXPECT_TRUE(TransformSupportsMatch(kScene, MatchMotion(), {}, {}, threshold));
}

}  // namespace
}  // namespace zeroreg
