#include "recordings/loop_consistency.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "recordings/synthetic_trajectory.hpp"

namespace zeroreg {
namespace {

using testing::CircleTrajectory;
using testing::DriftedOdometry;
using testing::InverseOf;
using testing::MakeTransform;
using testing::RandomMotion;

std::vector<double> PathLengths(const std::vector<Transform>& poses) {
  std::vector<double> lengths = {0.0};
  for (std::size_t i = 1; i < poses.size(); ++i) {
    lengths.push_back(
        lengths.back() +
        (poses[i].topRightCorner<3, 1>() - poses[i - 1].topRightCorner<3, 1>()).norm());
  }
  return lengths;
}

LoopClosure TrueLoop(const std::vector<Transform>& truth, int u, int v) {
  return {u, v, InverseOf(truth[static_cast<std::size_t>(u)]) * truth[static_cast<std::size_t>(v)]};
}

// One recording, two laps of a room: right loop closures between the laps, drifted odometry, and
// wrong loop closures planted among them (each off in its own random way).
TEST(LoopConsistency, RightLoopClosuresAgreeAndWrongOnesAreLeftOut) {
  const std::vector<Transform> truth = CircleTrajectory(60, 2.0, 2.0);
  const std::vector<Transform> odometry = DriftedOdometry(truth, 7);
  const OdometryContext context{odometry, std::vector<int>(60, 0), PathLengths(odometry)};
  std::vector<LoopClosure> loops;
  for (int i = 0; i < 30; i += 3) loops.push_back(TrueLoop(truth, i, i + 30));
  std::mt19937 rng(8);
  const std::vector<std::pair<int, int>> wrong_pairs = {{4, 35}, {17, 50}, {25, 58}};
  for (const auto& [u, v] : wrong_pairs) {
    LoopClosure wrong = TrueLoop(truth, u, v);
    wrong.T_u_v = wrong.T_u_v * RandomMotion(rng, 25.0, 0.8);
    loops.push_back(wrong);
  }
  const ConsistentLoopSet set = SelectConsistentLoops(loops, context);
  EXPECT_EQ(set.accepted, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_FALSE(set.ambiguous);
  EXPECT_TRUE(set.exact);
}

// Two recordings: B's odometry in a frame of its own (unknown offset to A's), loop closures
// between A's and B's keyframes, some of them run B -> A. The offset does not matter: only the
// cycles through each recording's own odometry are compared.
TEST(LoopConsistency, TwoRecordingsInUnrelatedFramesAreComparedThroughTheirCycles) {
  const std::vector<Transform> truth = CircleTrajectory(60, 2.5, 2.0);
  std::vector<Transform> odometry = DriftedOdometry(truth, 9);
  std::mt19937 rng(10);
  const Transform T_bframe_world = RandomMotion(rng, 140.0, 3.0);
  const std::vector<Transform> odometry_b = DriftedOdometry(truth, 11);
  for (std::size_t i = 30; i < odometry.size(); ++i) odometry[i] = T_bframe_world * odometry_b[i];
  std::vector<int> recording(60, 0);
  std::fill(recording.begin() + 30, recording.end(), 1);
  std::vector<double> lengths = PathLengths(truth);
  const OdometryContext context{odometry, recording, lengths};
  std::vector<LoopClosure> loops;
  for (int i = 0; i < 30; i += 5) loops.push_back(TrueLoop(truth, i, i + 30));
  loops.push_back(TrueLoop(truth, 52, 22));  // the other way round: B -> A
  LoopClosure wrong = TrueLoop(truth, 10, 45);
  wrong.T_u_v = wrong.T_u_v * RandomMotion(rng, 60.0, 1.5);
  loops.push_back(wrong);
  const ConsistentLoopSet set = SelectConsistentLoops(loops, context);
  EXPECT_EQ(set.accepted, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_FALSE(set.ambiguous);
}

// A symmetric place: wrong loop closures that are all wrong the same way (B placed turned half
// round about the room's vertical axis) agree with each other as well as the right ones do. The
// larger group is accepted, and the other is reported as a rival that makes the set ambiguous.
TEST(LoopConsistency, TwoGroupsThatEachAgreeAreAmbiguous) {
  const std::vector<Transform> truth = CircleTrajectory(60, 2.0, 2.0);
  const std::vector<Transform> odometry = truth;
  std::vector<int> recording(60, 0);
  std::fill(recording.begin() + 30, recording.end(), 1);
  const OdometryContext context{odometry, recording, PathLengths(truth)};
  const Transform half_turn =
      MakeTransform(M_PI, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
  std::vector<LoopClosure> loops;
  for (int i = 0; i < 30; i += 6) loops.push_back(TrueLoop(truth, i, i + 30));  // 5 right
  for (int i = 2; i < 30; i += 8) {  // 4 wrong, all by the same half turn of B
    loops.push_back({i, i + 30, InverseOf(truth[i]) * half_turn * truth[i + 30]});
  }
  const ConsistentLoopSet set = SelectConsistentLoops(loops, context);
  EXPECT_EQ(set.accepted, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(set.rival, (std::vector<int>{5, 6, 7, 8}));
  EXPECT_TRUE(set.ambiguous);

  LoopConsistencyConfig strict;
  strict.ambiguity_ratio = 0.9;  // 4 of 5 is below it
  EXPECT_FALSE(SelectConsistentLoops(loops, context, strict).ambiguous);
}

TEST(LoopConsistency, CandidatesOfWhichNoneAgreesAreAllLeftOut) {
  const std::vector<Transform> truth = CircleTrajectory(40, 2.0, 2.0);
  const OdometryContext context{truth, std::vector<int>(40, 0), PathLengths(truth)};
  std::mt19937 rng(12);
  std::vector<LoopClosure> loops;
  for (int i = 0; i < 4; ++i) {
    LoopClosure wrong = TrueLoop(truth, i * 5, i * 5 + 20);
    wrong.T_u_v = wrong.T_u_v * RandomMotion(rng, 40.0, 1.0);
    loops.push_back(wrong);
  }
  EXPECT_TRUE(SelectConsistentLoops(loops, context).accepted.empty());
  // A single candidate has nothing to disagree with.
  EXPECT_EQ(SelectConsistentLoops({loops[0]}, context).accepted, std::vector<int>{0});
  EXPECT_TRUE(SelectConsistentLoops({}, context).accepted.empty());
}

// The tolerance grows with the metres of odometry in the cycle: the same error is consistent over
// a long leg and not over a short one.
TEST(LoopConsistency, ToleranceGrowsWithTheOdometryPath) {
  CycleError error;
  error.rotation_deg = 6.0;
  error.translation_m = 0.12;
  error.lever_m = 1.0;
  const LoopConsistencyConfig config;
  error.odometry_path_m = 0.5;
  EXPECT_FALSE(CycleWithinTolerance(error, config));
  error.odometry_path_m = 10.0;
  EXPECT_TRUE(CycleWithinTolerance(error, config));
}

TEST(LoopConsistency, RefusesLoopsNamingNodesTheOdometryLacks) {
  const std::vector<Transform> truth = CircleTrajectory(10, 1.0);
  const OdometryContext context{truth, std::vector<int>(10, 0), PathLengths(truth)};
  EXPECT_THROW(SelectConsistentLoops({{0, 12, Transform::Identity()}}, context),
               std::invalid_argument);
  const OdometryContext short_paths{truth, std::vector<int>(10, 0), {0.0}};
  EXPECT_THROW(SelectConsistentLoops({{0, 3, Transform::Identity()}}, short_paths),
               std::invalid_argument);
}

}  // namespace
}  // namespace zeroreg
