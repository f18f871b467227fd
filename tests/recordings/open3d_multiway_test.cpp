// The Open3D multiway baseline (src/recordings/open3d_multiway.hpp) on a synthetic room with exact
// poses: two recordings that see the same furniture, B given in a frame of its own, must come out
// with T_A_B; a recording of unrelated geometry must not be placed.
#include "recordings/open3d_multiway.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "synthetic_trajectory.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using testing::InverseOf;

// A floor, two walls and boxes of different sizes, sampled every 3 cm (jittered).
std::vector<Eigen::Vector3d> Room(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.005, 0.005);
  std::vector<Eigen::Vector3d> points;
  auto plane = [&](const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                   const Eigen::Vector3d& v, double lu, double lv) {
    for (double a = 0; a <= lu; a += 0.03) {
      for (double b = 0; b <= lv; b += 0.03) {
        points.push_back(origin + a * u + b * v +
                         Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
      }
    }
  };
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  plane({-2, -2, 0}, x, y, 4, 4);    // floor
  plane({-2, 2, 0}, x, z, 4, 2.5);   // wall
  plane({-2, -2, 0}, y, z, 4, 2.5);  // wall
  const double boxes[][6] = {{-1.2, 1.2, 0, 0.6, 0.4, 0.9},
                             {0.3, 1.5, 0, 0.9, 0.3, 0.5},
                             {-1.6, -0.5, 0, 0.3, 0.8, 1.2},
                             {0.6, -0.2, 0, 0.5, 0.5, 0.4}};
  for (const auto& b : boxes) {
    const Eigen::Vector3d o(b[0], b[1], b[2]);
    plane(o, x, z, b[3], b[5]);
    plane(o + b[4] * y, x, z, b[3], b[5]);
    plane(o, y, z, b[4], b[5]);
    plane(o + b[3] * x, y, z, b[4], b[5]);
    plane(o + b[5] * z, x, y, b[3], b[4]);
  }
  return points;
}

// The points a camera at T_world_camera sees (in its frame): in front, within a 70 x 55 deg
// field of view and 5 m (no occlusion).
std::vector<Eigen::Vector3d> Seen(const std::vector<Eigen::Vector3d>& room,
                                  const Transform& T_world_camera) {
  const Transform T_camera_world = InverseOf(T_world_camera);
  std::vector<Eigen::Vector3d> seen;
  for (const Eigen::Vector3d& p : room) {
    const Eigen::Vector3d c =
        T_camera_world.topLeftCorner<3, 3>() * p + T_camera_world.topRightCorner<3, 1>();
    if (c.z() > 0.3 && c.z() < 5.0 && std::abs(c.x()) < 0.7 * c.z() &&
        std::abs(c.y()) < 0.52 * c.z()) {
      seen.push_back(c);
    }
  }
  return seen;
}

double RotationDeg(const Transform& T) {
  const double c = (T.topLeftCorner<3, 3>().trace() - 1.0) / 2.0;
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

MultiwayConfig FastConfig() {
  MultiwayConfig config;
  config.ransac_max_iterations = 10000;
  return config;
}

TEST(Open3dMultiway, PlacesAnUnalignedRecordingThatSeesTheSameRoom) {
  std::mt19937 rng(7);
  const std::vector<Eigen::Vector3d> room = Room(rng);
  // Cameras 2.6 m from the room's centre at 1.3 m height, looking at it: A on one arc, B on an
  // overlapping arc further round.
  const std::vector<Transform> circle = testing::CircleTrajectory(24, 2.6);
  const Transform T_Bframe_world = testing::RandomMotion(rng, 70.0, 2.0);
  std::vector<MultiwayKeyframe> keyframes;
  for (int k : {14, 15, 16, 17}) keyframes.push_back({0, Seen(room, circle[k]), circle[k]});
  for (int k : {16, 17, 18, 19}) {
    keyframes.push_back({1, Seen(room, circle[k]), T_Bframe_world * circle[k]});
  }
  const MultiwayResult result = RegisterMultiway(keyframes, FastConfig());
  ASSERT_TRUE(result.T_A_B.has_value());
  const Transform error = InverseOf(*result.T_A_B) * InverseOf(T_Bframe_world);
  EXPECT_LT(RotationDeg(error), 2.0);
  EXPECT_LT((error.topRightCorner<3, 1>().norm()), 0.05);
  EXPECT_EQ(result.loop_candidates, 8 * 7 / 2 - 6);  // 6 consecutive pairs are odometry
  int kept_bridges = 0;
  for (const MultiwayEdge& e : result.edges) {
    if (e.loop && e.kept && keyframes[e.source].recording != keyframes[e.target].recording) {
      ++kept_bridges;
    }
  }
  EXPECT_GE(kept_bridges, 1);
  for (bool placed : result.placed) EXPECT_TRUE(placed);
}

TEST(Open3dMultiway, UnrelatedRecordingIsNotPlaced) {
  std::mt19937 rng(8);
  const std::vector<Eigen::Vector3d> room = Room(rng);
  const std::vector<Transform> circle = testing::CircleTrajectory(24, 2.6);
  std::vector<MultiwayKeyframe> keyframes;
  for (int k : {14, 15, 16}) keyframes.push_back({0, Seen(room, circle[k]), circle[k]});
  // B: scattered points, nothing like the room.
  std::uniform_real_distribution<double> spread(-1.0, 1.0);
  for (int k = 0; k < 2; ++k) {
    std::vector<Eigen::Vector3d> noise;
    for (int i = 0; i < 1000; ++i) noise.emplace_back(spread(rng), spread(rng), 2.0 + spread(rng));
    keyframes.push_back({1, noise, std::nullopt});
  }
  const MultiwayResult result = RegisterMultiway(keyframes, FastConfig());
  EXPECT_FALSE(result.T_A_B.has_value());
  EXPECT_FALSE(result.placed[3]);
  EXPECT_FALSE(result.placed[4]);
  EXPECT_TRUE(result.placed[0]);
}

TEST(Open3dMultiway, RecordingBFirstIsRefused) {
  std::vector<MultiwayKeyframe> keyframes = {{1, {{0, 0, 1}}, std::nullopt}};
  EXPECT_THROW(RegisterMultiway(keyframes), InputError);
}

}  // namespace
}  // namespace zeroreg
