#include "viz/ply.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Back-projects the valid depth pixels of `view` into the scan frame, with the pixel colours.
void AppendViewPoints(const View& view, const CloudExportConfig& config, ColoredCloud* cloud) {
  const Intrinsics& k = view.intrinsics;
  if (view.depth.empty() || view.depth.type() != CV_32FC1 || k.fx <= 0 || k.fy <= 0) return;
  const bool has_color = view.color.type() == CV_8UC3 && view.color.size() == view.depth.size();
  const Eigen::Matrix3d R = view.T_scan_camera.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = view.T_scan_camera.topRightCorner<3, 1>();
  for (int v = 0; v < view.depth.rows; ++v) {
    const float* row = view.depth.ptr<float>(v);
    for (int u = 0; u < view.depth.cols; ++u) {
      const double z = row[u];
      if (!(z >= config.min_depth_m && z <= config.max_depth_m)) continue;
      const Eigen::Vector3d p((u - k.cx) * z / k.fx, (v - k.cy) * z / k.fy, z);
      cloud->points.push_back(R * p + t);
      if (has_color) {
        const cv::Vec3b bgr = view.color.at<cv::Vec3b>(v, u);
        cloud->colors.emplace_back(bgr[2] / 255.0, bgr[1] / 255.0, bgr[0] / 255.0);
      } else {
        cloud->colors.emplace_back(-1, -1, -1);  // replaced by the fallback colour below
      }
    }
  }
}

struct VoxelKeyHash {
  size_t operator()(const Eigen::Vector3i& k) const {
    // Large odd multipliers spread neighbouring voxels over the buckets.
    return static_cast<size_t>(k.x()) * 73856093u ^ static_cast<size_t>(k.y()) * 19349663u ^
           static_cast<size_t>(k.z()) * 83492791u;
  }
};

struct VoxelKeyEqual {
  bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
};

void PutLE(std::string* out, const void* bytes, size_t n) {
  // PLY binary_little_endian: copy as is on little-endian hosts, byte-swap otherwise.
  const auto* b = static_cast<const unsigned char*>(bytes);
  const uint16_t probe = 1;
  const bool little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
  for (size_t i = 0; i < n; ++i) out->push_back(static_cast<char>(little ? b[i] : b[n - 1 - i]));
}

uint8_t ToByte(double c) {
  return static_cast<uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
}

}  // namespace

ColoredCloud VoxelDownsample(const ColoredCloud& cloud, double voxel_m) {
  if (voxel_m <= 0) return cloud;
  struct Cell {
    Eigen::Vector3d point_sum = Eigen::Vector3d::Zero(), color_sum = Eigen::Vector3d::Zero();
    int count = 0;
  };
  std::unordered_map<Eigen::Vector3i, size_t, VoxelKeyHash, VoxelKeyEqual> index;
  std::vector<Cell> cells;  // first-seen order, so the output does not depend on the hash
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3d& p = cloud.points[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector3i key = (p / voxel_m).array().floor().cast<int>();
    auto [it, inserted] = index.emplace(key, cells.size());
    if (inserted) cells.emplace_back();
    Cell& c = cells[it->second];
    c.point_sum += p;
    if (i < cloud.colors.size()) c.color_sum += cloud.colors[i];
    ++c.count;
  }
  ColoredCloud out;
  out.points.reserve(cells.size());
  out.colors.reserve(cells.size());
  for (const Cell& c : cells) {
    out.points.push_back(c.point_sum / c.count);
    out.colors.push_back(c.color_sum / c.count);
  }
  return out;
}

ColoredCloud ScanGeometry(const Scan& scan, const Eigen::Vector3d& fallback_color,
                          const CloudExportConfig& config) {
  ColoredCloud cloud;
  if (!scan.points.empty()) {
    cloud.points = scan.points;
    if (scan.colors.size() == scan.points.size()) {
      cloud.colors = scan.colors;
    } else {
      cloud.colors.assign(scan.points.size(), fallback_color);
    }
  } else {
    for (const View& view : scan.views) AppendViewPoints(view, config, &cloud);
    for (Eigen::Vector3d& c : cloud.colors) {
      if (c.x() < 0) c = fallback_color;
    }
  }
  if (!config.use_scan_colors) cloud.colors.assign(cloud.points.size(), fallback_color);
  return VoxelDownsample(cloud, config.voxel_m);
}

void WritePly(const std::string& path, const ColoredCloud& cloud) {
  if (cloud.colors.size() != cloud.points.size()) {
    throw MakeInputError(path, "cannot write the PLY: " + std::to_string(cloud.points.size()) +
                                   " points but " + std::to_string(cloud.colors.size()) +
                                   " colours (expected one colour per point)");
  }
  std::string data =
      "ply\nformat binary_little_endian 1.0\ncomment written by zeroreg\nelement vertex " +
      std::to_string(cloud.points.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  data.reserve(data.size() + cloud.points.size() * 15);
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    for (int d = 0; d < 3; ++d) {
      const float x = static_cast<float>(cloud.points[i][d]);
      PutLE(&data, &x, sizeof(x));
    }
    for (int d = 0; d < 3; ++d) data.push_back(static_cast<char>(ToByte(cloud.colors[i][d])));
  }
  // Replaced atomically: a full disk keeps the previous file whole, and the error says why.
  detail::WriteFileAtomically(path, data);
}

RegisteredPlyFiles WriteRegisteredPly(const std::string& dir, const Scan& source,
                                      const Scan& target, const Transform& T_target_source,
                                      const CloudExportConfig& config) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw MakeInputError(dir, "cannot create the output folder (" + ec.message() + ")");
  const ColoredCloud source_cloud = ScanGeometry(source, kSourceColor, config);
  const ColoredCloud target_cloud = ScanGeometry(target, kTargetColor, config);

  ColoredCloud registered;
  registered.points = target_cloud.points;
  registered.colors.assign(target_cloud.points.size(), kTargetColor);
  const Eigen::Matrix3d R = T_target_source.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T_target_source.topRightCorner<3, 1>();
  for (const Eigen::Vector3d& p : source_cloud.points) registered.points.push_back(R * p + t);
  registered.colors.resize(registered.points.size(), kSourceColor);

  RegisteredPlyFiles files;
  const std::filesystem::path d(dir);
  files.registered = (d / "registered.ply").string();
  files.source = (d / "source.ply").string();
  files.target = (d / "target.ply").string();
  files.num_source = source_cloud.points.size();
  files.num_target = target_cloud.points.size();
  WritePly(files.registered, registered);
  WritePly(files.source, source_cloud);
  WritePly(files.target, target_cloud);
  return files;
}

}  // namespace zeroreg
