// Exact rigid motions for the synthetic tests of the estimators and of the object-match checks.
#pragma once

#include <Eigen/Geometry>

#include "zeroreg/types.hpp"

namespace zeroreg::testing {

// Rotation by angle_rad about `axis` (normalised here), then translation by t.
inline Transform MakeTransform(double angle_rad, const Eigen::Vector3d& axis,
                               const Eigen::Vector3d& t) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = t;
  return T;
}

// Stand-in poses for the decision-rule tests: a shift along x, a turn about z.
inline Transform ShiftedAlongX(double x_m) {
  return MakeTransform(0.0, Eigen::Vector3d::UnitZ(), Eigen::Vector3d(x_m, 0.0, 0.0));
}
inline Transform TurnedAboutZ(double deg) {
  return MakeTransform(deg * M_PI / 180.0, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
}

inline Eigen::Vector3d Apply(const Transform& T, const Eigen::Vector3d& p) {
  return (T * p.homogeneous()).head<3>();
}

}  // namespace zeroreg::testing
