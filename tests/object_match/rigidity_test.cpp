#include "object_match/rigidity.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace zeroreg {
namespace {

// Five objects of a room and the same room seen after a rigid motion (exact centroids).
struct Room {
  std::vector<Eigen::Vector3d> source, target;
};
Room MakeRoom() {
  Room room;
  room.source = {{0, 0, 2}, {1.5, 0, 3}, {-1, 0.5, 2.5}, {0.5, -0.8, 4}, {3.5, 1.2, 1.0}};
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -0.3, 1.2);
  for (const Eigen::Vector3d& p : room.source) room.target.push_back(R * p + t);
  return room;
}

std::vector<std::pair<int, int>> Pairs(const std::vector<ObjectPair>& pairs) {
  std::vector<std::pair<int, int>> out;
  for (const ObjectPair& p : pairs) out.emplace_back(p.source, p.target);
  return out;
}

TEST(Rigidity, DropsTheSwappedMatchAndKeepsTheConsistentOnes) {
  const Room room = MakeRoom();
  // 0-0, 1-1, 2-2 right; 3 matched to 4 (a same-label object elsewhere in the room).
  const std::vector<ObjectPair> pairs = {{0, 0, 1.9}, {1, 1, 1.8}, {2, 2, 1.7}, {3, 4, 1.95}};
  const RigidityCheck check = CheckRigidity(pairs, room.source, room.target, 0.3);
  EXPECT_EQ(Pairs(check.kept), (std::vector<std::pair<int, int>>{{0, 0}, {1, 1}, {2, 2}}));
  EXPECT_EQ(Pairs(check.dropped), (std::vector<std::pair<int, int>>{{3, 4}}));
}

TEST(Rigidity, CentroidNoiseWithinTheToleranceKeepsEveryRightMatch) {
  Room room = MakeRoom();
  // Partly seen objects: every target centroid moved by up to 0.12 m.
  const std::vector<Eigen::Vector3d> shifts = {
      {0.12, 0, 0}, {0, -0.1, 0.05}, {-0.08, 0.05, 0}, {0, 0, 0.11}, {0.05, 0.05, -0.05}};
  for (size_t i = 0; i < shifts.size(); ++i) room.target[i] += shifts[i];
  const std::vector<ObjectPair> pairs = {
      {0, 0, 1.9}, {1, 1, 1.8}, {2, 2, 1.7}, {3, 3, 1.6}, {4, 4, 1.5}};
  const RigidityCheck check = CheckRigidity(pairs, room.source, room.target, 0.3);
  EXPECT_EQ(check.kept.size(), 5u);
  EXPECT_TRUE(check.dropped.empty());
}

TEST(Rigidity, KeepsEverythingWhenNothingConfirmsOrContradicts) {
  const Room room = MakeRoom();
  // Two matches that disagree: neither is confirmed by a third, so both stay for §3.4 to judge.
  const std::vector<ObjectPair> two = {{0, 0, 1.9}, {3, 4, 1.8}};
  EXPECT_EQ(CheckRigidity(two, room.source, room.target, 0.3).kept.size(), 2u);
  const std::vector<ObjectPair> one = {{3, 4, 1.8}};
  EXPECT_EQ(CheckRigidity(one, room.source, room.target, 0.3).kept.size(), 1u);
  // Tolerance 0 switches the check off.
  const std::vector<ObjectPair> four = {{0, 0, 1.9}, {1, 1, 1.8}, {2, 2, 1.7}, {3, 4, 1.95}};
  EXPECT_EQ(CheckRigidity(four, room.source, room.target, 0.0).kept.size(), 4u);
}

TEST(Rigidity, BetweenTwoEqualSetsTheMoreSimilarWins) {
  const Room room = MakeRoom();
  // {0-0, 1-1} agree; {2-3, 3-2}: a swapped pair whose two distances agree with each other by
  // symmetry (|c2 - c3| is the same on both sides) but not with the first two.
  std::vector<ObjectPair> pairs = {{0, 0, 1.2}, {1, 1, 1.2}, {2, 3, 1.9}, {3, 2, 1.9}};
  RigidityCheck check = CheckRigidity(pairs, room.source, room.target, 0.3);
  EXPECT_EQ(Pairs(check.kept), (std::vector<std::pair<int, int>>{{2, 3}, {3, 2}}));
  pairs[0].node_similarity = pairs[1].node_similarity = 1.95;
  check = CheckRigidity(pairs, room.source, room.target, 0.3);
  EXPECT_EQ(Pairs(check.kept), (std::vector<std::pair<int, int>>{{0, 0}, {1, 1}}));
}

TEST(Rigidity, AnObjectSeenPartlyGetsTheChangeOfItsExtentAsSlack) {
  Room room = MakeRoom();
  // Object 1 (a table) is seen whole in the source and half in the target: its target centroid
  // moved 0.5 m, and its visible radius shrank from 0.8 to 0.4 m.
  room.target[1] += Eigen::Vector3d(0.5, 0, 0);
  const std::vector<ObjectPair> pairs = {{0, 0, 1.9}, {1, 1, 1.8}, {2, 2, 1.7}};
  EXPECT_EQ(CheckRigidity(pairs, room.source, room.target, 0.3).dropped.size(), 1u);
  const std::vector<double> radius_source = {0.2, 0.8, 0.2, 0.2, 0.2};
  const std::vector<double> radius_target = {0.2, 0.4, 0.2, 0.2, 0.2};
  const RigidityCheck check =
      CheckRigidity(pairs, room.source, room.target, 0.3, radius_source, radius_target);
  EXPECT_EQ(check.kept.size(), 3u);
  EXPECT_NEAR(RmsRadius({{0, 0, 0}, {2, 0, 0}}, {1, 0, 0}), 1.0, 1e-12);
  EXPECT_EQ(RmsRadius({}, {1, 0, 0}), 0.0);
}

}  // namespace
}  // namespace zeroreg
