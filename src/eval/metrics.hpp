// Registration error metrics (DESIGN §6). Eigen only.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// Nearest rotation matrix (SVD). Ground-truth rotations of 3DMatch / 7-Scenes are not exactly
// orthonormal (det down to 0.9996); without this a perfect estimate shows ~0.7 deg of error.
Eigen::Matrix3d Orthonormalize(const Eigen::Matrix3d& R);

// Angle of R_gt^T R_est in degrees, with R_gt orthonormalised first.
double RotationErrorDeg(const Transform& T_est, const Transform& T_gt);
// |t_est - t_gt| in metres.
double TranslationErrorM(const Transform& T_est, const Transform& T_gt);

// 3DMatch registration-recall error: with D = inv(T_gt) T_est, xi = [t(D); q_xyz(D)],
// E = xi^T Info xi / Info(0,0). A pair counts as registered when E <= 0.2^2.
double RegistrationRecallError(const Transform& T_est, const Transform& T_gt,
                               const Eigen::Matrix<double, 6, 6>& information);

// Fraction of correspondences whose source point, moved by T_gt, lands within `threshold_m` of
// its target point (3DMatch inlier ratio, threshold 0.1 m). 0 when there are none.
double CorrespondenceInlierRatio(const std::vector<Correspondence>& correspondences,
                                 const Transform& T_target_source_gt, double threshold_m = 0.1);

}  // namespace zeroreg
