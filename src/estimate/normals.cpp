#include "estimate/normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

namespace zeroreg {
namespace {

// Cell coordinates packed into one sortable key: 21 bits per axis, offset so that negative
// coordinates sort too. At a 6 cm radius that spans +-63 km, far beyond any scan.
constexpr std::int64_t kAxisOffset = std::int64_t{1} << 20;

std::int64_t CellKey(std::int64_t x, std::int64_t y, std::int64_t z) {
  return ((x + kAxisOffset) << 42) | ((y + kAxisOffset) << 21) | (z + kAxisOffset);
}

}  // namespace

std::vector<Eigen::Vector3d> EstimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             double radius, int max_neighbours) {
  const size_t n = points.size();
  std::vector<Eigen::Vector3d> normals(n, Eigen::Vector3d::UnitZ());
  if (n == 0 || !(radius > 0) || max_neighbours < 3) return normals;

  // The points sorted by grid cell (cell side = radius); each occupied cell is a range of `order`.
  std::vector<std::int64_t> cell_of(n);
  std::vector<Eigen::Vector3i> cell_coords(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3i c = (points[i] / radius).array().floor().cast<int>();
    cell_coords[i] = c;
    cell_of[i] = CellKey(c.x(), c.y(), c.z());
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return cell_of[a] != cell_of[b] ? cell_of[a] < cell_of[b] : a < b;
  });
  std::vector<std::int64_t> cell_keys;  // sorted, one per occupied cell
  std::vector<size_t> cell_begin;       // cell k is order[cell_begin[k], cell_begin[k + 1])
  for (size_t i = 0; i < n; ++i) {
    const std::int64_t key = cell_of[order[i]];
    if (cell_keys.empty() || cell_keys.back() != key) {
      cell_keys.push_back(key);
      cell_begin.push_back(i);
    }
  }
  cell_begin.push_back(n);
  // The points in cell order, so that a cell's points are read from consecutive memory.
  std::vector<Eigen::Vector3d> sorted(n);
  for (size_t i = 0; i < n; ++i) sorted[i] = points[order[i]];

  const double radius_sq = radius * radius;
  std::vector<std::pair<double, int>> candidates;  // (squared distance, index)
  std::vector<std::pair<size_t, size_t>> around;   // ranges of `order` of the 27 cells
  for (size_t cell = 0; cell + 1 < cell_begin.size(); ++cell) {
    // Every point of this cell has its neighbours in the same 27 cells.
    const Eigen::Vector3i c = cell_coords[order[cell_begin[cell]]];
    around.clear();
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const std::int64_t key = CellKey(c.x() + dx, c.y() + dy, c.z() + dz);
          const auto it = std::lower_bound(cell_keys.begin(), cell_keys.end(), key);
          if (it == cell_keys.end() || *it != key) continue;
          const size_t k = static_cast<size_t>(it - cell_keys.begin());
          around.emplace_back(cell_begin[k], cell_begin[k + 1]);
        }
      }
    }
    for (size_t q = cell_begin[cell]; q < cell_begin[cell + 1]; ++q) {
      const int query = order[q];
      const Eigen::Vector3d& p = sorted[q];
      candidates.clear();
      for (const auto& [begin, end] : around) {
        for (size_t j = begin; j < end; ++j) {
          const double d2 = (sorted[j] - p).squaredNorm();
          if (d2 <= radius_sq) candidates.emplace_back(d2, order[j]);
        }
      }
      // The closest max_neighbours, ranked by (distance, index): a total order, so the chosen set
      // does not depend on the order the cells were visited in. On a surface thinned to voxels
      // most points have fewer candidates than that (~28 within 3 voxels), and all are kept.
      const size_t keep = std::min(candidates.size(), static_cast<size_t>(max_neighbours));
      if (keep < 3) continue;
      if (keep < candidates.size()) {
        std::nth_element(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(keep),
                         candidates.end());
      }
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (size_t k = 0; k < keep; ++k) mean += points[candidates[k].second];
      mean /= static_cast<double>(keep);
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (size_t k = 0; k < keep; ++k) {
        const Eigen::Vector3d d = points[candidates[k].second] - mean;
        covariance.noalias() += d * d.transpose();
      }
      covariance /= static_cast<double>(keep);
      // The plane's normal: the direction of least spread. computeDirect is the closed-form 3x3
      // solution (as Open3D's fast normal computation); its eigenvalues come sorted ascending.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(covariance);
      const Eigen::Vector3d normal = solver.eigenvectors().col(0);
      const double length = normal.norm();
      if (length > 0 && std::isfinite(length)) normals[query] = normal / length;
    }
  }
  return normals;
}

}  // namespace zeroreg
