#include "estimate/voxel_filter.hpp"

#include <cmath>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <unordered_map>

namespace zeroreg {
namespace {

struct VoxelKey {
  int x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

// boost's hash_combine over the three integers, in x, y, z order: the hash Open3D 0.16 gives its
// voxel map (utility::hash_eigen), so that the map iterates in the order Open3D's did.
struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    std::size_t seed = 0;
    for (int v : {k.x, k.y, k.z}) {
      seed ^= std::hash<int>()(v) + 0x9e3779b9 + (seed << 6) + (seed >> 2);
    }
    return seed;
  }
};

struct Sum {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double value = 0.0;
  int count = 0;
};

}  // namespace

VoxelMeans VoxelDownSample(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<double>& values, double voxel_m) {
  if (!(voxel_m > 0)) throw std::invalid_argument("VoxelDownSample: voxel_m must be > 0");
  if (!values.empty() && values.size() != points.size()) {
    throw std::invalid_argument("VoxelDownSample: values must be empty or one per point");
  }
  VoxelMeans out;
  if (points.empty()) return out;
  Eigen::Vector3d min_corner = points.front();
  for (const Eigen::Vector3d& p : points) min_corner = min_corner.cwiseMin(p);
  const Eigen::Vector3d origin = min_corner - Eigen::Vector3d::Constant(voxel_m * 0.5);
  std::unordered_map<VoxelKey, Sum, VoxelKeyHash> voxels;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d cell = (points[i] - origin) / voxel_m;
    const VoxelKey key{static_cast<int>(std::floor(cell.x())),
                       static_cast<int>(std::floor(cell.y())),
                       static_cast<int>(std::floor(cell.z()))};
    Sum& s = voxels[key];
    s.point += points[i];
    if (!values.empty()) s.value += values[i];
    ++s.count;
  }
  out.points.reserve(voxels.size());
  if (!values.empty()) out.values.reserve(voxels.size());
  for (const auto& [key, s] : voxels) {
    const double n = static_cast<double>(s.count);
    out.points.push_back(s.point / n);
    if (!values.empty()) out.values.push_back(s.value / n);
  }
  return out;
}

}  // namespace zeroreg
