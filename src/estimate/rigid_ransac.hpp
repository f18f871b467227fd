// Rigid transform from 3D correspondences: closed-form least squares (Kabsch / Umeyama without
// scale) and a deterministic RANSAC around it (paper §3.4, "we then use RANSAC").
//
// Why not Open3D's RegistrationRANSACBasedOnCorrespondence: it samples in parallel threads, so the
// same input and seed can give a different transform from run to run. This RANSAC draws every
// sample from one seeded generator, so the output is a function of (input, config, seed) only.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// Least-squares rigid transform T minimising sum |T * source_i - target_i|^2 over `indices` (all
// points when empty). Needs at least 3 non-collinear points; returns false otherwise.
bool FitRigidTransform(const std::vector<Eigen::Vector3d>& source,
                       const std::vector<Eigen::Vector3d>& target, const std::vector<int>& indices,
                       Transform* T_target_source);

struct RansacResult {
  bool found = false;  // false when no non-degenerate sample was found
  Transform T_target_source = Transform::Identity();
  std::vector<bool> is_inlier;  // parallel to the correspondences
  int num_inliers = 0;
  double inlier_rmse = 0.0;  // metres
  int iterations = 0;
};

// The final step of every estimator: the inliers of result->T_target_source (residual below
// inlier_threshold_m over all correspondences), least-squares refits on them until the set stops
// changing (never trading inliers for a refit), then is_inlier, num_inliers and inlier_rmse.
void RefitOnInliers(const std::vector<Eigen::Vector3d>& source,
                    const std::vector<Eigen::Vector3d>& target, double inlier_threshold_m,
                    RansacResult* result);

// RANSAC with 3-point samples, a rigidity pre-check on each sample (pairwise distances must agree
// within 2 x inlier threshold), MSAC scoring, adaptive stopping at config.confidence, and a final
// least-squares refit on the inliers repeated until the inlier set is stable.
RansacResult EstimateRigidRansac(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const RansacConfig& config, std::uint64_t seed);

}  // namespace zeroreg
