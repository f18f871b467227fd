#pragma once

#include "zeroreg/types.hpp"

namespace zeroreg {

// The inverse of a rigid transform, [R t]^-1 = [R^T  -R^T t]: exact and cheaper than a general
// 4x4 inverse, and it keeps the bottom row exactly (0 0 0 1).
inline Transform RigidInverse(const Transform& T) {
  Transform inverse = Transform::Identity();
  inverse.topLeftCorner<3, 3>() = T.topLeftCorner<3, 3>().transpose();
  inverse.topRightCorner<3, 1>() = -T.topLeftCorner<3, 3>().transpose() * T.topRightCorner<3, 1>();
  return inverse;
}

}  // namespace zeroreg
