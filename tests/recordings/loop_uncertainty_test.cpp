#include "recordings/loop_uncertainty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "recordings/synthetic_trajectory.hpp"

namespace zeroreg {
namespace {

using testing::MakeTransform;

// Points on a `size_m` cube's corners and faces, `distance_m` in front of the source camera.
std::vector<Eigen::Vector3d> Surface(double size_m, double distance_m) {
  std::vector<Eigen::Vector3d> points;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      points.emplace_back(0.25 * size_m * i, 0.25 * size_m * j, distance_m);
      points.emplace_back(0.25 * size_m * i, 0.5 * size_m, distance_m + 0.25 * size_m * j);
    }
  }
  return points;
}

// The predicted covariance matches the spread of least-squares fits (Umeyama) to noisy copies of
// the same correspondences: the fits' rotation error and the source camera's position error
// against the truth, over many draws.
TEST(LoopUncertainty, PredictsTheSpreadOfTheFitUnderNoise) {
  const Transform T = MakeTransform(0.4, Eigen::Vector3d(0.2, 1.0, 0.1), {0.5, -0.2, 1.5});
  const std::vector<Eigen::Vector3d> source = Surface(0.6, 2.0);
  const double noise = 0.01;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, noise);
  const int draws = 400;
  double rotation_sq = 0.0, position_sq = 0.0;
  LoopUncertainty predicted;
  for (int draw = 0; draw < draws; ++draw) {
    Eigen::Matrix3Xd from(3, source.size()), to(3, source.size());
    std::vector<Eigen::Vector3d> target;
    for (std::size_t i = 0; i < source.size(); ++i) {
      target.push_back((T * source[i].homogeneous()).head<3>() +
                       Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
      from.col(static_cast<Eigen::Index>(i)) = source[i];
      to.col(static_cast<Eigen::Index>(i)) = target.back();
    }
    const Transform fit = Eigen::umeyama(from, to, false);
    const LoopUncertainty u = UncertaintyOfFit(source, target, fit);
    ASSERT_TRUE(u.determined);
    EXPECT_NEAR(u.point_sigma_m, noise, 0.3 * noise);
    if (draw == 0) predicted = u;
    const Eigen::AngleAxisd error(
        Eigen::Matrix3d(fit.topLeftCorner<3, 3>() * T.topLeftCorner<3, 3>().transpose()));
    rotation_sq += std::pow(error.angle(), 2) / draws;
    position_sq += (fit.topRightCorner<3, 1>() - T.topRightCorner<3, 1>()).squaredNorm() / draws;
  }
  const double rotation_trace = predicted.covariance.topLeftCorner<3, 3>().trace();
  const double position_trace = predicted.covariance.bottomRightCorner<3, 3>().trace();
  EXPECT_NEAR(std::sqrt(rotation_sq), std::sqrt(rotation_trace), 0.2 * std::sqrt(rotation_trace));
  EXPECT_NEAR(std::sqrt(position_sq), std::sqrt(position_trace), 0.2 * std::sqrt(position_trace));
  // The 2 m lever makes the camera's position less certain than the centroid's sigma/sqrt(N).
  EXPECT_GT(predicted.translation_sigma_m, 2.0 * noise / std::sqrt(50.0));
}

// The same correspondences seen from twice as far: the rotation is as well known relative to the
// points, the source camera's position less.
TEST(LoopUncertainty, TheCamerasPositionGrowsLessCertainWithTheLever) {
  const Transform T = Transform::Identity();
  const auto sigma = [&](double distance_m) {
    const std::vector<Eigen::Vector3d> source = Surface(0.6, distance_m);
    std::vector<Eigen::Vector3d> target;
    std::mt19937 same(5);
    std::normal_distribution<double> n(0.0, 0.01);
    for (const Eigen::Vector3d& p : source) {
      target.push_back(p + Eigen::Vector3d(n(same), n(same), n(same)));
    }
    return UncertaintyOfFit(source, target, T);
  };
  const LoopUncertainty near = sigma(1.0), far = sigma(3.0);
  EXPECT_NEAR(far.rotation_sigma_rad, near.rotation_sigma_rad, 0.2 * near.rotation_sigma_rad);
  EXPECT_GT(far.translation_sigma_m, 2.0 * near.translation_sigma_m);
}

// Two points, or any number on a line, leave a rotation free: no bound.
TEST(LoopUncertainty, FewerThanThreePointsOrALineDetermineNothing) {
  const Transform T = Transform::Identity();
  std::vector<Eigen::Vector3d> two = {{0, 0, 1}, {0.3, 0.1, 1.2}};
  LoopUncertainty u = UncertaintyOfFit(two, two, T);
  EXPECT_FALSE(u.determined);
  EXPECT_TRUE(std::isinf(u.rotation_sigma_rad));
  EXPECT_TRUE(std::isinf(u.translation_sigma_m));
  std::vector<Eigen::Vector3d> line, moved;
  for (int i = 0; i < 20; ++i) {
    line.emplace_back(0.1 * i, 0.05 * i, 1.0 + 0.02 * i);
    moved.push_back(line.back() + Eigen::Vector3d(0.001 * (i % 3), -0.001 * (i % 2), 0.0));
  }
  u = UncertaintyOfFit(line, moved, T);
  EXPECT_FALSE(u.determined);
  EXPECT_TRUE(std::isinf(u.translation_sigma_m));
  EXPECT_THROW(UncertaintyOfFit(line, two, T), std::invalid_argument);
}

// A registration's inliers only: the outliers do not count.
TEST(LoopUncertainty, OfARegistrationUsesItsInliers) {
  RegistrationResult r;
  r.T_target_source = Transform::Identity();
  for (const Eigen::Vector3d& p : Surface(0.6, 2.0)) {
    Correspondence c;
    c.source = p;
    c.target = p;
    r.correspondences.push_back(c);
    r.is_inlier.push_back(r.is_inlier.size() < 2);
  }
  EXPECT_FALSE(UncertaintyOfRegistration(r).determined);
  r.is_inlier.assign(r.correspondences.size(), true);
  r.correspondences[7].target.x() += 0.01;
  EXPECT_TRUE(UncertaintyOfRegistration(r).determined);
}

}  // namespace
}  // namespace zeroreg
