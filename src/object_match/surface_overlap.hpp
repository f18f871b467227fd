// Do two objects' surfaces coincide under a rigid motion?
//
// Each object carries its surface as 3D points (its masks' depth pixels, one per 2 cm voxel;
// SceneObject::points). Under the motion between the scans, two observations of one physical
// object put part of their surfaces in the same place, however much of it each saw (a counter
// seen at either end still shares the stretch both saw); two different objects share none unless
// they touch. Used by object_match.agree_with_result under the returned transform and by the
// evaluation's surface measure under the ground truth.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// True when at least min_share of either object's points, the source's moved into the target
// frame by T_target_source, lie within radius_m of the other object's points. False when either
// has no points.
bool SurfacesCoincide(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target, const Transform& T_target_source,
                      double radius_m, double min_share);

}  // namespace zeroreg
