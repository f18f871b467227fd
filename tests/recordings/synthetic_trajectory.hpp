// Synthetic keyframe trajectories with exact poses, for the tests of the pose graph and of the loop
// consistency: a camera walking around a room and looking inward, the odometry drifted as
// ../shared/sessions/README.md's protocol drifts it, and loop closures taken from the truth.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "rigid_motion.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg::testing {

inline Transform InverseOf(const Transform& T) {
  Transform inverse = Transform::Identity();
  inverse.topLeftCorner<3, 3>() = T.topLeftCorner<3, 3>().transpose();
  inverse.topRightCorner<3, 1>() = -T.topLeftCorner<3, 3>().transpose() * T.topRightCorner<3, 1>();
  return inverse;
}

// `n` camera poses T_world_camera on a circle of `radius_m` (z up), `turns` times around, each
// camera looking at the centre, with a gentle height wave so the graph is not planar.
inline std::vector<Transform> CircleTrajectory(int n, double radius_m, double turns = 1.0) {
  std::vector<Transform> poses;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * turns * i / n;
    const Eigen::Vector3d position(radius_m * std::cos(a), radius_m * std::sin(a),
                                   1.2 + 0.2 * std::sin(3 * a));
    // Camera z (optical axis) toward the centre, x along the walk, y down.
    const Eigen::Vector3d z = -Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    const Eigen::Vector3d y(0.0, 0.0, -1.0);
    const Eigen::Vector3d x = y.cross(z);
    Transform T = Transform::Identity();
    T.block<3, 1>(0, 0) = x;
    T.block<3, 1>(0, 1) = y;
    T.block<3, 1>(0, 2) = z;
    T.topRightCorner<3, 1>() = position;
    poses.push_back(T);
  }
  return poses;
}

// A random rotation of `angle_deg` about a random axis and a translation of `distance_m` in a
// random direction.
inline Transform RandomMotion(std::mt19937& rng, double angle_deg, double distance_m) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  const Eigen::Vector3d direction(normal(rng), normal(rng), normal(rng));
  return MakeTransform(angle_deg * M_PI / 180.0, axis, distance_m * direction.normalized());
}

// Odometry of `truth`: every frame-to-frame motion composed with an error of `translation_fraction`
// of its translation (random direction) and `rotation_deg` (random axis); starts at truth[0].
inline std::vector<Transform> DriftedOdometry(const std::vector<Transform>& truth, unsigned seed,
                                              double translation_fraction = 0.01,
                                              double rotation_deg = 0.1) {
  std::mt19937 rng(seed);
  std::vector<Transform> odometry = {truth.front()};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const Transform step = InverseOf(truth[i - 1]) * truth[i];
    const double length = step.topRightCorner<3, 1>().norm();
    odometry.push_back(odometry.back() * step *
                       RandomMotion(rng, rotation_deg, translation_fraction * length));
  }
  return odometry;
}

// Root mean square of the position errors of `estimate` against `truth`, in metres (both in the
// same frame).
inline double TrajectoryRmse(const std::vector<Transform>& estimate,
                             const std::vector<Transform>& truth) {
  double sum = 0.0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    sum += (estimate[i].topRightCorner<3, 1>() - truth[i].topRightCorner<3, 1>()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

}  // namespace zeroreg::testing
