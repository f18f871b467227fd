#include "estimate/icp.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "estimate/depth_noise.hpp"
#include "estimate/lift.hpp"
#include "estimate/normals.hpp"
#include "estimate/point_kd_tree.hpp"
#include "estimate/voxel_filter.hpp"
#include "parallel/parallel_for.hpp"

namespace zeroreg {
namespace {

Eigen::Matrix3d SkewSymmetric(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

struct IcpGeometry::Level {
  double voxel_m = 0;
  // Thinned points, with normals once MakeTargetReady ran. Mutable for that one write of the
  // normals (under target_once); the points never change, so sources may read them meanwhile.
  std::vector<Eigen::Vector3d> points;
  mutable std::vector<Eigen::Vector3d> normals;
  std::vector<double> camera_depth;  // per thinned point; empty when unknown

  // Normals and k-d tree, made once however many threads ask (the thinned points stay as they
  // are: a source only reads them).
  const PointKdTree& MakeTargetReady() const {
    std::call_once(target_once, [this] {
      if (points.size() < 6) return;
      // Open3D's rule (the 30 closest within 3 voxels), found in a grid instead of a k-d tree.
      normals = EstimateNormals(points, 3 * voxel_m, 30);
      tree = std::make_unique<PointKdTree>(points);
    });
    return *tree;
  }

 private:
  mutable std::once_flag target_once;
  mutable std::unique_ptr<PointKdTree> tree;
};

IcpGeometry::IcpGeometry() = default;
IcpGeometry::~IcpGeometry() = default;
IcpGeometry::IcpGeometry(const IcpGeometry&) = default;
IcpGeometry& IcpGeometry::operator=(const IcpGeometry&) = default;

IcpGeometry::IcpGeometry(const std::vector<Eigen::Vector3d>& points,
                         const std::vector<IcpStage>& stages, bool as_target,
                         const std::vector<double>& camera_depth) {
  if (!camera_depth.empty() && camera_depth.size() != points.size()) {
    throw std::invalid_argument("IcpGeometry: camera_depth must be empty or one per point");
  }
  // Each resolution thins the raw points; the depth readings are averaged like the points.
  for (const IcpStage& stage : stages) {
    if (stage.iterations <= 0 || !(stage.voxel_m > 0)) continue;
    const bool built = std::any_of(levels_.begin(), levels_.end(),
                                   [&](const auto& l) { return l->voxel_m == stage.voxel_m; });
    if (built) continue;
    auto level = std::make_shared<Level>();
    level->voxel_m = stage.voxel_m;
    VoxelMeans thinned = VoxelDownSample(points, camera_depth, stage.voxel_m);
    level->points = std::move(thinned.points);
    level->camera_depth = std::move(thinned.values);
    if (as_target) level->MakeTargetReady();
    levels_.push_back(std::move(level));
  }
}

IcpGeometry ScanIcpGeometry(const Scan& scan, const std::vector<IcpStage>& stages, bool as_target,
                            int pixel_stride) {
  std::vector<double> camera_depth;
  // Auto (RefineConfig::pixel_stride): twice the other stages' grid, or the same grid where the
  // depth is noisy. Every other pixel lets each 2 cm voxel average several readings of a thin
  // surface; a noisy surface is thicker than a voxel, so more readings fill more voxels instead
  // (twice the points, three times the iterations, no better fit: docs/CONFIG.md "Depth noise").
  int columns = 2 * kGridColumns;
  if (pixel_stride == 0 && scan.points.empty()) {
    const std::optional<double> noise = MeasureDepthNoiseAt1m(scan);
    if (noise && *noise > kNoisyDepthAt1mM) columns = kGridColumns;
  }
  const PixelGrid grid{pixel_stride, columns};
  const std::vector<Eigen::Vector3d> points = ScanPoints(scan, grid, 0.0, 1e9, &camera_depth);
  return IcpGeometry(points, stages, as_target, camera_depth);
}

size_t IcpGeometry::NumPoints(double voxel_m) const {
  for (const auto& l : levels_) {
    if (l->voxel_m == voxel_m) return l->points.size();
  }
  return 0;
}

size_t IcpGeometry::MemoryBytes() const {
  size_t bytes = 0;
  // Points and normals, plus the k-d tree's copy of the points and its nodes (about as much again;
  // counted whether or not they are made yet: what the scan holds once it was a target).
  for (const auto& l : levels_) {
    bytes +=
        l->points.size() * 4 * sizeof(Eigen::Vector3d) + l->camera_depth.size() * sizeof(double);
  }
  return bytes;
}

namespace {

// Gauss-Newton steps of point-to-plane ICP at one resolution; updates *T and *result. The
// closest-point search is the costly part and the only parallel one: each source point's
// neighbour is found independently, then the sums run serially in point order.
void RunStage(const IcpGeometry::Level& source_level, const IcpGeometry::Level& target_level,
              const PointKdTree& tree, const IcpStage& stage, const IcpAnchors& anchors,
              int threads, Transform* T, IcpResult* result) {
  const std::vector<Eigen::Vector3d>& source = source_level.points;
  const std::vector<Eigen::Vector3d>& target_points = target_level.points;
  const std::vector<Eigen::Vector3d>& target_normals = target_level.normals;
  const double gate_sq = stage.max_distance_m * stage.max_distance_m;
  // Depth-noise weights: a pair's point-to-plane residual has about the variance of the two depth
  // readings' axial noise (the normal is mostly along the view ray where the surface is seen
  // well). Floored at 1 mm, the depth quantisation near the camera. A scan without readings (a
  // fused cloud) adds no variance; with neither, every pair weighs the same.
  // Per point once per stage, not per iteration: empty where the scan has no readings.
  const auto depth_variances = [&](const std::vector<double>& depth) {
    std::vector<double> variance;
    if (!(stage.depth_noise_at_1m_m > 0)) return variance;
    variance.reserve(depth.size());
    for (double d : depth) {
      const double sigma =
          std::max(1e-3, stage.depth_noise_at_1m_m * std::pow(d, stage.depth_noise_exponent));
      variance.push_back(sigma * sigma);
    }
    return variance;
  };
  const std::vector<double> source_variance = depth_variances(source_level.camera_depth);
  const std::vector<double> target_variance = depth_variances(target_level.camera_depth);
  const bool noise_weights = !source_variance.empty() || !target_variance.empty();
  std::vector<Eigen::Vector3d> moved(source.size());
  std::vector<int> nearest(source.size());
  std::vector<double> nearest_sq(source.size());
  for (int it = 0; it < stage.iterations; ++it) {
    const Transform current = *T;
    ParallelFor(source.size(), threads, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        moved[i] = (current * source[i].homogeneous()).head<3>();
        double distance_sq = 0.0;
        nearest[i] = tree.Nearest(moved[i], gate_sq, &distance_sq);
        nearest_sq[i] = nearest[i] >= 0 ? distance_sq : 0.0;
      }
    });
    // Linearised point-to-plane residual n^T (R p + t - q) with R ~ I + [w]x, x = [w; t].
    Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> Jtr = Eigen::Matrix<double, 6, 1>::Zero();
    int matched = 0;
    double sum_sq = 0, sum_weight = 0;
    for (size_t i = 0; i < source.size(); ++i) {
      if (nearest[i] < 0) continue;
      const Eigen::Vector3d& p = moved[i];
      const Eigen::Vector3d& q = target_points[nearest[i]];
      const Eigen::Vector3d& n = target_normals[nearest[i]];
      Eigen::Matrix<double, 6, 1> J;
      J << p.cross(n), n;
      const double r = n.dot(p - q);
      const double weight =
          noise_weights ? 1.0 / ((source_variance.empty() ? 0.0 : source_variance[i]) +
                                 (target_variance.empty() ? 0.0 : target_variance[nearest[i]]))
                        : 1.0;
      JtJ += weight * J * J.transpose();
      Jtr += weight * J * r;
      sum_weight += weight;
      ++matched;
      sum_sq += nearest_sq[i];
    }
    // Anchors: r = p - q with p = T s, d p / d[w; t] = [-[p]x, I] for the update R ~ I + [w]x.
    // Both kinds of evidence get an equal say: the anchors in the gate together weigh as much as
    // the closest-point pairs (a few hundred image matches against thousands of depth samples
    // would otherwise be outvoted exactly where the depth is weak).
    Eigen::Matrix<double, 6, 6> anchor_JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> anchor_Jtr = Eigen::Matrix<double, 6, 1>::Zero();
    int anchored = 0;
    for (size_t k = 0; stage.anchor_weight > 0 && k < anchors.source.size(); ++k) {
      const Eigen::Vector3d p = (*T * anchors.source[k].homogeneous()).head<3>();
      const Eigen::Vector3d r = p - anchors.target[k];
      if (r.squaredNorm() > gate_sq) continue;
      Eigen::Matrix<double, 3, 6> J;
      J << -SkewSymmetric(p), Eigen::Matrix3d::Identity();
      anchor_JtJ += J.transpose() * J;
      anchor_Jtr += J.transpose() * r;
      ++anchored;
    }
    if (anchored > 0) {
      const double w = stage.anchor_weight * std::max(1.0, sum_weight) / (3.0 * anchored);
      JtJ += w * anchor_JtJ;
      Jtr += w * anchor_Jtr;
    }
    ++result->iterations;
    result->fitness = static_cast<double>(matched) / source.size();
    result->rmse = matched > 0 ? std::sqrt(sum_sq / matched) : 0.0;
    if (matched < 6) return;
    const Eigen::Matrix<double, 6, 1> x = JtJ.ldlt().solve(-Jtr);
    if (!x.allFinite()) return;
    Transform step = Transform::Identity();
    const double angle = x.head<3>().norm();
    if (angle > 0) {
      step.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle, x.head<3>() / angle).toRotationMatrix();
    }
    step.topRightCorner<3, 1>() = x.tail<3>();
    *T = step * *T;
    // Converged: a step below 0.1 mm and 0.1 mrad (0.006 deg) is far below the depth noise;
    // iterating on only re-shuffles closest-point pairs.
    if (x.head<3>().norm() < 1e-4 && x.tail<3>().norm() < 1e-4) return;
  }
}

}  // namespace

std::vector<IcpStage> IcpSchedule(const RefineConfig& config, const DepthModel& depth) {
  const double noise = depth.noise_at_1m_m, power = depth.noise_exponent;
  return {{config.voxel_coarse_m, config.max_distance_coarse_m, config.coarse_iterations,
           config.anchor_weight_coarse, noise, power},
          {config.voxel_m, config.max_distance_m, config.max_iterations, config.anchor_weight_fine,
           noise, power},
          {config.voxel_m, config.max_distance_final_m, config.max_iterations,
           config.anchor_weight_fine, noise, power}};
}

IcpResult RefinePointToPlane(const IcpGeometry& source, const IcpGeometry& target,
                             const Transform& initial, const std::vector<IcpStage>& stages,
                             const IcpAnchors& anchors, int threads) {
  IcpResult result;
  Transform T = initial;
  const auto level = [](const IcpGeometry& g, double voxel_m) -> const IcpGeometry::Level* {
    for (const auto& l : g.levels_) {
      if (l->voxel_m == voxel_m) return l.get();
    }
    return nullptr;
  };
  for (const IcpStage& stage : stages) {
    if (stage.iterations <= 0 || !(stage.voxel_m > 0)) continue;
    const IcpGeometry::Level* s = level(source, stage.voxel_m);
    const IcpGeometry::Level* t = level(target, stage.voxel_m);
    if (s == nullptr || t == nullptr) {
      throw std::logic_error("RefinePointToPlane: geometry not built for this ICP schedule");
    }
    if (s->points.size() < 6 || t->points.size() < 6) break;
    const PointKdTree& tree = t->MakeTargetReady();
    RunStage(*s, *t, tree, stage, anchors, threads, &T, &result);
  }
  result.T_target_source = T;
  return result;
}

IcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const Transform& initial,
                             const std::vector<IcpStage>& stages, const IcpAnchors& anchors,
                             int threads) {
  return RefinePointToPlane(IcpGeometry(source, stages), IcpGeometry(target, stages), initial,
                            stages, anchors, threads);
}

}  // namespace zeroreg
