#include "estimate/rigid_ransac.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>

namespace zeroreg {

bool FitRigidTransform(const std::vector<Eigen::Vector3d>& source,
                       const std::vector<Eigen::Vector3d>& target, const std::vector<int>& indices,
                       Transform* T_target_source) {
  const size_t n = indices.empty() ? source.size() : indices.size();
  if (n < 3) return false;
  auto index = [&](size_t k) { return indices.empty() ? static_cast<int>(k) : indices[k]; };
  Eigen::Vector3d mean_s = Eigen::Vector3d::Zero(), mean_t = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < n; ++k) {
    mean_s += source[index(k)];
    mean_t += target[index(k)];
  }
  mean_s /= static_cast<double>(n);
  mean_t /= static_cast<double>(n);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < n; ++k) {
    covariance += (target[index(k)] - mean_t) * (source[index(k)] - mean_s).transpose();
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Collinear or coincident points leave the rotation about their line undetermined.
  const Eigen::Vector3d sv = svd.singularValues();
  if (sv(1) <= 1e-12 * std::max(1.0, sv(0))) return false;
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2, 2) = -1;  // no mirror
  const Eigen::Matrix3d R = svd.matrixU() * d * svd.matrixV().transpose();
  T_target_source->setIdentity();
  T_target_source->topLeftCorner<3, 3>() = R;
  T_target_source->topRightCorner<3, 1>() = mean_t - R * mean_s;
  return true;
}

namespace {

// MSAC cost of a hypothesis (sum of truncated squared residuals) and its inlier count.
double ScoreHypothesis(const Transform& T, const std::vector<Eigen::Vector3d>& source,
                       const std::vector<Eigen::Vector3d>& target, double threshold_sq,
                       int* num_inliers) {
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T.topRightCorner<3, 1>();
  double cost = 0;
  int inliers = 0;
  for (size_t i = 0; i < source.size(); ++i) {
    const double r2 = (R * source[i] + t - target[i]).squaredNorm();
    if (r2 < threshold_sq) {
      cost += r2;
      ++inliers;
    } else {
      cost += threshold_sq;
    }
  }
  *num_inliers = inliers;
  return cost;
}

std::vector<int> InlierIndices(const Transform& T, const std::vector<Eigen::Vector3d>& source,
                               const std::vector<Eigen::Vector3d>& target, double threshold_sq) {
  std::vector<int> inliers;
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T.topRightCorner<3, 1>();
  for (size_t i = 0; i < source.size(); ++i) {
    if ((R * source[i] + t - target[i]).squaredNorm() < threshold_sq) {
      inliers.push_back(static_cast<int>(i));
    }
  }
  return inliers;
}

}  // namespace

void RefitOnInliers(const std::vector<Eigen::Vector3d>& source,
                    const std::vector<Eigen::Vector3d>& target, double inlier_threshold_m,
                    RansacResult* result_ptr) {
  RansacResult& result = *result_ptr;
  const double threshold_sq = inlier_threshold_m * inlier_threshold_m;
  std::vector<int> inliers = InlierIndices(result.T_target_source, source, target, threshold_sq);
  for (int round = 0; round < 10; ++round) {
    Transform refined;
    if (!FitRigidTransform(source, target, inliers, &refined)) break;
    std::vector<int> refined_inliers = InlierIndices(refined, source, target, threshold_sq);
    if (refined_inliers.size() < inliers.size()) break;  // never trade inliers for a refit
    result.T_target_source = refined;
    const bool stable = refined_inliers == inliers;
    inliers = std::move(refined_inliers);
    if (stable) break;
  }
  double sum_sq = 0;
  const Eigen::Matrix3d R = result.T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = result.T_target_source.topRightCorner<3, 1>();
  for (int i : inliers) {
    result.is_inlier[i] = true;
    sum_sq += (R * source[i] + t - target[i]).squaredNorm();
  }
  result.num_inliers = static_cast<int>(inliers.size());
  result.inlier_rmse = inliers.empty() ? 0.0 : std::sqrt(sum_sq / inliers.size());
}

RansacResult EstimateRigidRansac(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const RansacConfig& config, std::uint64_t seed) {
  RansacResult result;
  const int n = static_cast<int>(source.size());
  result.is_inlier.assign(source.size(), false);
  if (n < 3) return result;

  const double threshold = config.inlier_threshold_m;
  const double threshold_sq = threshold * threshold;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, n - 1);

  double best_cost = std::numeric_limits<double>::infinity();
  long long max_iterations = config.max_iterations;
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    int s[3] = {pick(rng), pick(rng), pick(rng)};
    if (s[0] == s[1] || s[0] == s[2] || s[1] == s[2]) continue;
    // A rigid motion preserves distances: reject samples whose pairwise distances disagree.
    bool rigid = true;
    for (int a = 0; a < 3 && rigid; ++a) {
      const int b = (a + 1) % 3;
      const double ds = (source[s[a]] - source[s[b]]).norm();
      const double dt = (target[s[a]] - target[s[b]]).norm();
      rigid = std::abs(ds - dt) < 2 * threshold && ds > threshold;
    }
    if (!rigid) continue;
    Transform T;
    if (!FitRigidTransform(source, target, {s[0], s[1], s[2]}, &T)) continue;
    int inliers = 0;
    const double cost = ScoreHypothesis(T, source, target, threshold_sq, &inliers);
    if (cost < best_cost) {
      best_cost = cost;
      result.T_target_source = T;
      result.found = true;
      // Adaptive stop: enough iterations that an all-inlier sample was drawn with `confidence`.
      const double w = static_cast<double>(inliers) / n;
      const double p_all_inlier = w * w * w;
      if (p_all_inlier > 1e-12) {
        const double needed =
            p_all_inlier >= 1.0 ? 1.0
                                : std::log(1.0 - config.confidence) / std::log(1.0 - p_all_inlier);
        max_iterations =
            std::min<long long>(config.max_iterations, static_cast<long long>(std::ceil(needed)));
      }
    }
  }
  result.iterations = iteration;
  if (!result.found) return result;

  // Least-squares refit on the inliers until the set stops changing (a few rounds at most).
  RefitOnInliers(source, target, config.inlier_threshold_m, &result);
  return result;
}

}  // namespace zeroreg
