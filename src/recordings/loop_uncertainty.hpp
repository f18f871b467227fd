// How well a pair registration's own evidence pins its transform: the covariance of a rigid
// least-squares fit to the correspondences that support it (its inliers), the noise estimated
// from their residuals. A loop closure that two or three correspondences carry, or one placed by
// dense alignment alone, says little about where its far end lies, however well its depth agrees:
// a fraction of a degree about the surface it sees moves a camera 1.5 m away by centimetres.
// Eigen only.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct LoopUncertainty {
  // False when the correspondences cannot fix a rigid transform: fewer than three, or all on a
  // line (the normal equations are singular); the sigmas are then infinite.
  bool determined = false;
  // Covariance of the fit, as a perturbation of T_target_source = [R, t]: R' = exp(w) R (w in
  // radians, the target frame's axes), t' = t + dt (metres). dt is the error of the source
  // camera's position in the target frame, the translation the loop closure's error is measured
  // by, and it grows with the rotation's uncertainty times the distance of the points from the
  // source camera.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  // Square roots of the largest eigenvalue of the rotation and of the translation block: the
  // standard deviation along the least determined axis.
  double rotation_sigma_rad = 0.0;
  double translation_sigma_m = 0.0;
  double point_sigma_m = 0.0;  // the per-axis noise of a correspondence, from the residuals
  int points = 0;
};

// The uncertainty of T_target_source fitted to target[i] ~ T * source[i]: per-axis noise
// sigma^2 = sum of squared residuals / (3N - 6) (three equations per point, six unknowns), and
// covariance sigma^2 (sum J_i^T J_i)^-1 with J_i = [-[R source_i]_x, I]. Throws
// std::invalid_argument when the vectors differ in length.
LoopUncertainty UncertaintyOfFit(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const Transform& T_target_source);

// The same over a registration's inlier correspondences under its T_target_source.
LoopUncertainty UncertaintyOfRegistration(const RegistrationResult& result);

}  // namespace zeroreg
