#include "eval/metrics.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace zeroreg {

Eigen::Matrix3d Orthonormalize(const Eigen::Matrix3d& R) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2, 2) = -1;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

double RotationErrorDeg(const Transform& T_est, const Transform& T_gt) {
  const Eigen::Matrix3d R_gt = Orthonormalize(T_gt.topLeftCorner<3, 3>());
  const Eigen::Matrix3d R_est = T_est.topLeftCorner<3, 3>();
  const double c = std::clamp(((R_gt.transpose() * R_est).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

double TranslationErrorM(const Transform& T_est, const Transform& T_gt) {
  return (T_est.topRightCorner<3, 1>() - T_gt.topRightCorner<3, 1>()).norm();
}

double RegistrationRecallError(const Transform& T_est, const Transform& T_gt,
                               const Eigen::Matrix<double, 6, 6>& information) {
  const Transform D = T_gt.inverse() * T_est;
  const Eigen::Quaterniond q(Orthonormalize(D.topLeftCorner<3, 3>()));
  Eigen::Matrix<double, 6, 1> xi;
  xi << D.topRightCorner<3, 1>(), q.x(), q.y(), q.z();
  // The sign of q is arbitrary; the 3DMatch reference uses w >= 0 implicitly for small errors.
  if (q.w() < 0) xi.tail<3>() *= -1;
  return (xi.transpose() * information * xi)(0, 0) / information(0, 0);
}

double CorrespondenceInlierRatio(const std::vector<Correspondence>& correspondences,
                                 const Transform& T_target_source_gt, double threshold_m) {
  if (correspondences.empty()) return 0.0;
  const Eigen::Matrix3d R = T_target_source_gt.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T_target_source_gt.topRightCorner<3, 1>();
  int inliers = 0;
  for (const Correspondence& c : correspondences) {
    if ((R * c.source + t - c.target).norm() < threshold_m) ++inliers;
  }
  return static_cast<double>(inliers) / correspondences.size();
}

}  // namespace zeroreg
