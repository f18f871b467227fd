#include "object_match/motion_agreement.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "rigid_motion.hpp"

namespace zeroreg {
namespace {

using testing::Apply;
using testing::MakeTransform;

// The scene's true motion between the two scans.
const Transform kScene = MakeTransform(0.6, {0.1, 1, 0.2}, {0.5, -0.2, 0.9});

// The inliers of an object of `n` surface points around `centre` (a `size` m cube), seen in both
// scans under `truth`; `noise_m` on the target points.
MatchMotion Object(const Eigen::Vector3d& centre, double size, int n, const Transform& truth,
                   double noise_m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5 * size, 0.5 * size);
  std::normal_distribution<double> e(0.0, noise_m);
  MatchMotion m;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = centre + Eigen::Vector3d(u(rng), u(rng), u(rng));
    m.source.push_back(p);
    m.target.push_back(Apply(truth, p) + Eigen::Vector3d(e(rng), e(rng), e(rng)));
  }
  return m;
}

// A right match: its points move with the scene and its own motion is the scene's.
MatchMotion Right(const Eigen::Vector3d& centre, unsigned seed) {
  return Object(centre, 0.5, 30, kScene, 0.01, seed);
}

// A wrong match (another object of the same class 1.2 m away): its points are consistent with
// one rigid motion, but not the scene's.
MatchMotion Wrong(const Eigen::Vector3d& centre, unsigned seed) {
  const Transform off = MakeTransform(0.0, {0, 0, 1}, {1.2, 0, 0}) * kScene;
  return Object(centre, 0.5, 30, off, 0.01, seed);
}

TEST(MotionAgreement, DropsTheMatchThatMovesDifferently) {
  const std::vector<MatchMotion> motions = {Right({0, 0, 2}, 1), Wrong({1, 0, 3}, 2),
                                            Right({-1, 0.5, 2.5}, 3), Right({0.5, -0.8, 4}, 4)};
  EXPECT_TRUE(MotionsAgree(motions[0], motions[2], 0.1));
  EXPECT_FALSE(MotionsAgree(motions[0], motions[1], 0.1));
  EXPECT_EQ(MatchesThatMoveTogether(motions, 0.1), (std::vector<int>{0, 2, 3}));
}

TEST(MotionAgreement, WithoutAStrictMajorityEveryMatchStays) {
  // Two matches that disagree: which one is wrong cannot be told.
  EXPECT_EQ(MatchesThatMoveTogether({Right({0, 0, 2}, 1), Wrong({1, 0, 3}, 2)}, 0.1),
            (std::vector<int>{0, 1}));
  // Two against two (the two wrong ones are the same wrong object pair, so they agree).
  EXPECT_EQ(MatchesThatMoveTogether({Right({0, 0, 2}, 1), Wrong({1, 0, 3}, 2),
                                     Right({-1, 0.5, 2.5}, 3), Wrong({1.1, 0, 3}, 4)},
                                    0.1),
            (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(MatchesThatMoveTogether({Right({0, 0, 2}, 1)}, 0.1), (std::vector<int>{0}));
  EXPECT_TRUE(MatchesThatMoveTogether({}, 0.1).empty());
}

TEST(MotionAgreement, TheConsensusIsEmptyWhenNothingIsDecided) {
  EXPECT_EQ(
      MatchesInConsensus({Right({0, 0, 2}, 1), Wrong({1, 0, 3}, 2), Right({-1, 0.5, 2.5}, 3)}, 0.1),
      (std::vector<int>{0, 2}));
  EXPECT_TRUE(MatchesInConsensus({Right({0, 0, 2}, 1), Wrong({1, 0, 3}, 2)}, 0.1).empty());
  EXPECT_TRUE(MatchesInConsensus({Right({0, 0, 2}, 1)}, 0.1).empty());  // one is no agreement
  EXPECT_TRUE(MatchesInConsensus({}, 0.1).empty());
}

// Two chairs of one class: Eq. 2 gave source chair 2 the target chair 5 (the motion agreement
// dropped it); its right partner, target chair 4, moves with the consensus and joins. A candidate
// of an object the consensus uses, one moving otherwise and one with three inliers do not.
TEST(MotionAgreement, CompleteByMotionAddsTheLeftOutPairThatMovesWithTheConsensus) {
  const std::vector<MotionCandidate> consensus = {{0, 0, Right({0, 0, 2}, 1)},
                                                  {1, 1, Right({-1, 0.5, 2.5}, 2)}};
  MotionCandidate few{3, 6, Right({0.3, 0.2, 3}, 7)};
  few.motion.source.resize(3);
  few.motion.target.resize(3);
  const std::vector<MotionCandidate> candidates = {
      {2, 5, Wrong({1, 0, 3}, 3)},        // the wrong chair: moves otherwise
      {2, 4, Right({1.1, 0, 3}, 4)},      // the right chair
      {0, 3, Right({0.2, 0, 2}, 5)},      // source 0 is taken by the consensus
      few,                                // three inliers fit any motion
      {3, 4, Right({0.5, -0.8, 4}, 6)}};  // target 4 goes to source 2 first (more inliers)
  std::vector<MotionCandidate> weaker = candidates;
  weaker[4].motion.source.resize(20);
  weaker[4].motion.target.resize(20);
  EXPECT_EQ(CompleteByMotion(consensus, weaker, 4, 0.1), (std::vector<int>{1}));
  // The wrong chair alone does not join: its motion is not the consensus's.
  EXPECT_TRUE(CompleteByMotion(consensus, {candidates[0]}, 4, 0.1).empty());
  // Without a consensus nothing joins.
  EXPECT_TRUE(CompleteByMotion({}, candidates, 4, 0.1).empty());
}

TEST(MotionAgreement, ASmallObjectIsJudgedTogetherWithALargeOne) {
  // A cup of 5 points within 8 cm (its own motion is poorly determined) and a table: one motion
  // fitted to both explains both when they move together, and not when the cup moved elsewhere.
  const MatchMotion cup = Object({0.3, 0.1, 2.2}, 0.08, 5, kScene, 0.005, 7);
  const MatchMotion table = Object({0, 0.4, 2.5}, 1.5, 200, kScene, 0.01, 8);
  EXPECT_TRUE(MotionsAgree(cup, table, 0.1));
  EXPECT_TRUE(MotionsAgree(table, cup, 0.1));
  const Transform elsewhere = MakeTransform(0.0, {0, 0, 1}, {0.6, 0, 0}) * kScene;
  const MatchMotion other_cup = Object({0.3, 0.1, 2.2}, 0.08, 5, elsewhere, 0.005, 7);
  EXPECT_FALSE(MotionsAgree(other_cup, table, 0.1));
}

TEST(MotionAgreement, APartlySeenObjectAgreesWhateverItsCentroid) {
  // The same table, seen whole in one scan and a third of it in the other: its matched points are
  // the visible third, which moves with the scene; the centroids of the two views would be 0.5 m
  // apart, but motions do not look at centroids.
  const MatchMotion third = Object({0.5, 0.4, 2.5}, 0.5, 60, kScene, 0.01, 9);
  const std::vector<MatchMotion> motions = {Right({0, 0, 2}, 1), third, Right({-1, 0.5, 2.5}, 3)};
  EXPECT_EQ(MatchesThatMoveTogether(motions, 0.1), (std::vector<int>{0, 1, 2}));
}

TEST(MotionAgreement, AMatchWithoutInliersAgreesWithNone) {
  // Fewer than three point matches give no inliers: such a match agrees with nothing, even in a
  // scene that does not move.
  const Transform still = Transform::Identity();
  MatchMotion none;  // no inliers
  const MatchMotion a = Object({0, 0, 2}, 0.5, 30, still, 0.01, 1);
  const MatchMotion b = Object({1, 0, 3}, 0.5, 30, still, 0.01, 2);
  EXPECT_FALSE(MotionsAgree(none, a, 0.1));
  EXPECT_FALSE(MotionsAgree(a, none, 0.1));
  EXPECT_EQ(MatchesThatMoveTogether({a, none, b}, 0.1), (std::vector<int>{0, 2}));
}

TEST(MotionAgreement, CountCarriedCountsThePointPairsTheMotionBringsTogether) {
  // 30 points of a right match follow the scene; the wrong match's are 1.2 m off under it.
  const MatchMotion right = Right({0, 0, 2}, 4), wrong = Wrong({1, 0, 2}, 5);
  EXPECT_EQ(CountCarried(kScene, right, 0.1), 30);
  EXPECT_EQ(CountCarried(kScene, wrong, 0.1), 0);
  EXPECT_EQ(CountCarried(Transform::Identity(), right, 0.1), 0);
  // The threshold is inclusive and applies to each pair's own distance: one pair 5 cm off.
  MatchMotion one;
  one.source = {Eigen::Vector3d(0, 0, 2)};
  one.target = {Apply(kScene, one.source[0]) + Eigen::Vector3d(0.05, 0, 0)};
  EXPECT_EQ(CountCarried(kScene, one, 0.05 + 1e-12), 1);
  EXPECT_EQ(CountCarried(kScene, one, 0.049), 0);
  EXPECT_EQ(CountCarried(kScene, MatchMotion(), 0.1), 0);
}

}  // namespace
}  // namespace zeroreg
