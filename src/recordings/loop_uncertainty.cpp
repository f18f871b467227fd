#include "recordings/loop_uncertainty.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace zeroreg {

LoopUncertainty UncertaintyOfFit(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const Transform& T_target_source) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("UncertaintyOfFit: " + std::to_string(source.size()) +
                                " source points and " + std::to_string(target.size()) +
                                " target points; expected pairs");
  }
  LoopUncertainty u;
  u.points = static_cast<int>(source.size());
  u.rotation_sigma_rad = std::numeric_limits<double>::infinity();
  u.translation_sigma_m = std::numeric_limits<double>::infinity();
  if (source.size() < 3) return u;
  const Eigen::Matrix3d R = T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T_target_source.topRightCorner<3, 1>();
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  double squared = 0.0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d a = R * source[i];
    squared += (a + t - target[i]).squaredNorm();
    Eigen::Matrix<double, 3, 6> J;
    // d(exp(w) R p + t + dt)/d(w, dt) at 0: w x a = -[a]_x w.
    J.leftCols<3>() << 0.0, a.z(), -a.y(), -a.z(), 0.0, a.x(), a.y(), -a.x(), 0.0;
    J.rightCols<3>().setIdentity();
    normal += J.transpose() * J;
  }
  const double dof = 3.0 * static_cast<double>(source.size()) - 6.0;
  u.point_sigma_m = std::sqrt(squared / dof);
  // Points on a line leave the rotation about it free: the normal matrix is singular (up to
  // rounding, relative to its largest eigenvalue).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(normal);
  const double largest = eigen.eigenvalues().maxCoeff();
  if (!(eigen.eigenvalues().minCoeff() > 1e-9 * largest)) return u;
  u.determined = true;
  u.covariance = u.point_sigma_m * u.point_sigma_m * normal.inverse();
  const Eigen::Matrix3d rotation = u.covariance.topLeftCorner<3, 3>();
  const Eigen::Matrix3d translation = u.covariance.bottomRightCorner<3, 3>();
  u.rotation_sigma_rad =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(rotation).eigenvalues().maxCoeff());
  u.translation_sigma_m = std::sqrt(
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(translation).eigenvalues().maxCoeff());
  return u;
}

LoopUncertainty UncertaintyOfRegistration(const RegistrationResult& result) {
  std::vector<Eigen::Vector3d> source, target;
  for (std::size_t i = 0; i < result.correspondences.size() && i < result.is_inlier.size(); ++i) {
    if (!result.is_inlier[i]) continue;
    source.push_back(result.correspondences[i].source);
    target.push_back(result.correspondences[i].target);
  }
  return UncertaintyOfFit(source, target, result.T_target_source);
}

}  // namespace zeroreg
