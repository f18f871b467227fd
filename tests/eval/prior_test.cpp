// The simulated motion prior of `zeroreg eval --prior-error-deg/-m`: exactly the asked error from
// the truth, the same for a pair in every run, another for another pair or seed.
#include "eval/prior.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace zeroreg {
namespace {

Transform SomePose() {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(0.4, -1.2, 2.5);
  return T;
}

double RotationDeg(const Transform& D) {
  const double c = std::clamp((D.topLeftCorner<3, 3>().trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

TEST(PriorOffTheTruth, IsExactlyTheAskedErrorFromTheTruth) {
  const Transform T_gt = SomePose();
  PriorError error;
  error.rotation_deg = 5.0;
  error.translation_m = 0.1;
  error.max_rotation_deg = 12.0;
  error.max_translation_m = 0.25;
  for (const char* key : {"frames/scene 0 8", "frames/scene 10 18", "3DLoMatch/x 2 15"}) {
    const MotionPrior prior = PriorOffTheTruth(T_gt, error, 0, key);
    const Transform D = T_gt.inverse() * prior.T_target_source;
    EXPECT_NEAR(RotationDeg(D), 5.0, 1e-9) << key;
    EXPECT_NEAR((D.topRightCorner<3, 1>().norm()), 0.1, 1e-12) << key;
    // The translation error a scorer measures (|t_prior - t_gt|) is the same 0.1 m.
    const Eigen::Vector3d moved = (prior.T_target_source - T_gt).topRightCorner<3, 1>();
    EXPECT_NEAR(moved.norm(), 0.1, 1e-12) << key;
    EXPECT_DOUBLE_EQ(prior.max_rotation_deg, 12.0);
    EXPECT_DOUBLE_EQ(prior.max_translation_m, 0.25);
  }
  error.rotation_deg = error.translation_m = 0.0;
  EXPECT_TRUE(PriorOffTheTruth(T_gt, error, 3, "k").T_target_source.isApprox(T_gt, 1e-12));
}

TEST(PriorOffTheTruth, SamePairAndSeedSamePriorOtherwiseAnother) {
  const Transform T_gt = SomePose();
  PriorError error;
  error.rotation_deg = 10.0;
  error.translation_m = 0.2;
  const Transform a = PriorOffTheTruth(T_gt, error, 0, "frames/s 0 8").T_target_source;
  EXPECT_EQ(a, PriorOffTheTruth(T_gt, error, 0, "frames/s 0 8").T_target_source);  // bit for bit
  EXPECT_FALSE(a.isApprox(PriorOffTheTruth(T_gt, error, 0, "frames/s 1 9").T_target_source, 1e-6));
  EXPECT_FALSE(a.isApprox(PriorOffTheTruth(T_gt, error, 1, "frames/s 0 8").T_target_source, 1e-6));
}

TEST(PriorOffTheTruth, AxesSpreadOverTheSphere) {
  // Over many pairs the rotation axes of the offsets average to about zero (no favoured side).
  PriorError error;
  error.rotation_deg = 90.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const Transform D =
        PriorOffTheTruth(Transform::Identity(), error, 0,
                         "frames/s " + std::to_string(k) + " " + std::to_string(k + 8))
            .T_target_source;
    const Eigen::AngleAxisd aa(Eigen::Matrix3d(D.topLeftCorner<3, 3>()));
    sum += aa.axis();
  }
  EXPECT_LT((sum / n).norm(), 0.08);  // |mean| of n uniform unit vectors ~ 1/sqrt(n) = 0.022
}

}  // namespace
}  // namespace zeroreg
