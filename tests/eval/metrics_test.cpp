#include "eval/metrics.hpp"

#include <gtest/gtest.h>

namespace zeroreg {
namespace {

Transform Rotation(double deg, const Eigen::Vector3d& axis) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  return T;
}

TEST(Metrics, RotationAndTranslationErrors) {
  Transform gt = Rotation(30, {0, 0, 1});
  gt.topRightCorner<3, 1>() << 1, 2, 3;
  Transform est = gt * Rotation(5, {1, 0, 0});
  est.topRightCorner<3, 1>() << 1.03, 2.0, 2.96;
  EXPECT_NEAR(RotationErrorDeg(est, gt), 5.0, 1e-9);
  EXPECT_NEAR(TranslationErrorM(est, gt), 0.05, 1e-12);
}

TEST(Metrics, NonOrthonormalGroundTruthGivesZeroErrorForItsNearestRotation) {
  Transform gt = Rotation(20, {1, 1, 0});
  gt.topLeftCorner<3, 3>() *= 0.9998;  // like the 3DMatch files: det slightly below 1
  Transform est = Transform::Identity();
  est.topLeftCorner<3, 3>() = Orthonormalize(gt.topLeftCorner<3, 3>());
  EXPECT_LT(RotationErrorDeg(est, gt), 1e-3);  // acos near 1 resolves ~1e-6 deg
}

TEST(Metrics, RegistrationRecallErrorMatchesHandComputedValue) {
  // With Info = identity, E = |t|^2 + |q_xyz|^2; for a rotation of angle a about z and
  // translation (0.1, 0, 0): E = 0.01 + sin^2(a/2).
  Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Identity();
  Transform est = Rotation(10, {0, 0, 1});
  est(0, 3) = 0.1;
  const double expected = 0.01 + std::pow(std::sin(5.0 * M_PI / 180.0), 2);
  EXPECT_NEAR(RegistrationRecallError(est, Transform::Identity(), info), expected, 1e-12);
  EXPECT_NEAR(RegistrationRecallError(Transform::Identity(), Transform::Identity(), info), 0.0,
              1e-15);
}

TEST(Metrics, CorrespondenceInlierRatio) {
  std::vector<Correspondence> c(4);
  for (int i = 0; i < 4; ++i) c[i].source = c[i].target = Eigen::Vector3d(i, 0, 1);
  c[3].target.x() += 0.5;
  EXPECT_DOUBLE_EQ(CorrespondenceInlierRatio(c, Transform::Identity()), 0.75);
  EXPECT_DOUBLE_EQ(CorrespondenceInlierRatio({}, Transform::Identity()), 0.0);
}

}  // namespace
}  // namespace zeroreg
