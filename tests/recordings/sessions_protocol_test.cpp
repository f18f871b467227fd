// The sessions protocol's seeded unalignment and drift, and the trajectory error.
#include "eval/sessions_protocol.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "eval/metrics.hpp"
#include "synthetic_trajectory.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

std::map<int, Transform> Circle(int n) {
  std::map<int, Transform> poses;
  const std::vector<Transform> list = testing::CircleTrajectory(n, 2.0);
  for (int i = 0; i < n; ++i) poses[10 + i] = list[static_cast<std::size_t>(i)];
  return poses;
}

TEST(SessionsProtocolTest, UnalignmentIsRigidSeededAndWithinThreeMetres) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Transform T = SeededUnalignment(seed);
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LE((T.topRightCorner<3, 1>().norm()), 3.0);
    EXPECT_EQ(T, SeededUnalignment(seed));
  }
  EXPECT_NE(SeededUnalignment(0), SeededUnalignment(1));
}

TEST(SessionsProtocolTest, DriftKeepsTheFirstPoseAndErrsByTheProtocolsAmountPerStep) {
  const std::map<int, Transform> truth = Circle(100);
  const std::map<int, Transform> drifted = DriftedOdometry(truth, 3);
  ASSERT_EQ(drifted.size(), truth.size());
  EXPECT_EQ(drifted.begin()->second, truth.begin()->second);
  EXPECT_EQ(drifted, DriftedOdometry(truth, 3));
  EXPECT_NE(drifted, DriftedOdometry(truth, 4));
  // Each step's motion differs from the truth's by 0.1 deg and 1 % of its length.
  auto t = truth.begin(), d = drifted.begin();
  auto t_next = std::next(t), d_next = std::next(d);
  for (; t_next != truth.end(); ++t, ++d, ++t_next, ++d_next) {
    const Transform true_motion = t->second.inverse() * t_next->second;
    const Transform drifted_motion = d->second.inverse() * d_next->second;
    EXPECT_NEAR(RotationErrorDeg(drifted_motion, true_motion), 0.1, 1e-6);
    const Transform error = true_motion.inverse() * drifted_motion;
    const double error_m = error.topRightCorner<3, 1>().norm();
    const double step_m = true_motion.topRightCorner<3, 1>().norm();
    EXPECT_NEAR(error_m, 0.01 * step_m, 1e-9);
  }
  EXPECT_GT(AbsoluteTrajectoryError(drifted, truth), 0.0);
}

TEST(SessionsProtocolTest, TrajectoryErrorIsTheRmsOfPositionsOverSharedFrames) {
  std::map<int, Transform> truth = Circle(4), estimate = truth;
  EXPECT_DOUBLE_EQ(AbsoluteTrajectoryError(estimate, truth), 0.0);
  estimate[10](0, 3) += 0.2;             // one of four frames 20 cm off: RMSE 10 cm
  estimate[99] = Transform::Identity();  // not in the truth: ignored
  EXPECT_NEAR(AbsoluteTrajectoryError(estimate, truth), 0.1, 1e-12);
  EXPECT_TRUE(std::isnan(AbsoluteTrajectoryError({}, truth)));
  EXPECT_EQ(Moved(Transform::Identity(), truth), truth);
}

std::string WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

// The message of the InputError ReadSessionSplits throws for `path` ("" when none).
std::string ErrorOf(const std::string& path) {
  try {
    ReadSessionSplits(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SessionSplitsTest, ReadsTheSharedListAndSkipsHeaderAndComments) {
  const auto dir = testing::FreshTestDir("zeroreg_sessions_");
  const std::string path = WriteFile(dir / "s.tsv",
                                     "scene\tA\tB\n# a comment\n\nroom\t0-499\t600-999\r\n"
                                     "desk\t3-150\t175-378\n");
  const std::vector<SessionSplit> splits = ReadSessionSplits(path);
  ASSERT_EQ(splits.size(), 2u);
  EXPECT_EQ(splits[0].scene, "room");
  EXPECT_EQ(splits[0].a_first, 0);
  EXPECT_EQ(splits[0].a_last, 499);
  EXPECT_EQ(splits[0].b_first, 600);
  EXPECT_EQ(splits[0].b_last, 999);
  EXPECT_EQ(splits[1].scene, "desk");
  EXPECT_EQ(splits[1].b_last, 378);
  const std::string shared = testing::SharedDir() + "/sessions/sessions.tsv";
  if (std::filesystem::exists(shared)) {
    const std::vector<SessionSplit> three = ReadSessionSplits(shared);
    ASSERT_EQ(three.size(), 3u);
    EXPECT_EQ(three[2].scene, "tum-fr3-cabinet");
    EXPECT_EQ(three[2].b_first, 34);
  }
  std::filesystem::remove_all(dir);
}

TEST(SessionSplitsTest, BadFilesAreNamedWithTheLineAndWhatWasExpected) {
  const auto dir = testing::FreshTestDir("zeroreg_sessions_");
  const std::string missing = (dir / "none.tsv").string();
  EXPECT_NE(ErrorOf(missing).find(missing + ": cannot read"), std::string::npos);
  const std::string empty = WriteFile(dir / "empty.tsv", "scene\tA\tB\n");
  EXPECT_NE(ErrorOf(empty).find("no split listed"), std::string::npos);
  const std::string short_line = WriteFile(dir / "short.tsv", "scene\tA\tB\nroom\t0-9\n");
  EXPECT_NE(ErrorOf(short_line).find(short_line + ":2: expected scene<TAB>A<TAB>B"),
            std::string::npos);
  for (const std::string range : {"9-3", "0-", "a-b", "0-9x", "-3-5"}) {
    const std::string bad = WriteFile(dir / "bad.tsv", "room\t0-9\t" + range + "\n");
    EXPECT_NE(ErrorOf(bad).find(bad + ":1: '" + range + "': expected a frame range FIRST-LAST"),
              std::string::npos)
        << range << ": " << ErrorOf(bad);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace zeroreg
