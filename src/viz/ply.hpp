// Registered clouds as coloured PLY files, for viewers such as MeshLab, CloudCompare or Open3D:
//   target.ply      the target's geometry in the target frame, in its own colours;
//   source.ply      the source's geometry in the source frame, in its own colours;
//   registered.ply  the target's points (blue) followed by the source's points moved into the
//                   target frame by T_target_source (orange) — the same colours as the
//                   registered-view<i>.png pictures. Where the registration is right the two
//                   colours interleave on the same surfaces.
// A scan's geometry is its point cloud when it has one (a fused fragment), else its views' depth
// back-projected into the scan frame; either way voxel-downsampled (1 cm by default).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// Origin colours of registered.ply, RGB in [0, 1] (the pictures' blue and orange).
inline const Eigen::Vector3d kTargetColor(30 / 255.0, 120 / 255.0, 200 / 255.0);
inline const Eigen::Vector3d kSourceColor(250 / 255.0, 140 / 255.0, 30 / 255.0);

struct ColoredCloud {
  std::vector<Eigen::Vector3d> points;  // metres
  std::vector<Eigen::Vector3d> colors;  // RGB in [0, 1], same size as points
};

struct CloudExportConfig {
  // Voxel edge for the downsampling, metres; <= 0 keeps every point. Each occupied voxel becomes
  // the mean of its points and colours. 1 cm keeps the shape and makes a 640x480 frame ~50k points.
  double voxel_m = 0.01;
  // Depth pixels outside [min_depth_m, max_depth_m] are not back-projected (sensor noise at the
  // ends of the Kinect range).
  double min_depth_m = 0.1;
  double max_depth_m = 6.0;
  // source.ply / target.ply in the scans' own colours (true) or in the origin colours (false).
  bool use_scan_colors = true;
};

// The scan's geometry in the scan frame with its colours (scan.colors, or the views' colour
// images; the origin colour when there are none), voxel-downsampled. Deterministic: points come
// out in the order their voxel was first seen.
ColoredCloud ScanGeometry(const Scan& scan, const Eigen::Vector3d& fallback_color,
                          const CloudExportConfig& config = CloudExportConfig());

// Mean point and colour per voxel of edge `voxel_m` (<= 0: a copy), in first-seen order.
ColoredCloud VoxelDownsample(const ColoredCloud& cloud, double voxel_m);

// Writes a binary little-endian PLY: float x, y, z and uchar red, green, blue per vertex.
// Throws InputError naming `path` if the file cannot be written or the sizes differ.
void WritePly(const std::string& path, const ColoredCloud& cloud);

struct RegisteredPlyFiles {
  std::string registered, source, target;  // paths written
  size_t num_source = 0, num_target = 0;   // points in each (registered.ply holds both)
};

// Writes registered.ply, source.ply and target.ply into `dir` (created if needed). In
// registered.ply the target's points come first, then the source's, so that vertex
// num_target + k is T_target_source times vertex k of source.ply.
RegisteredPlyFiles WriteRegisteredPly(const std::string& dir, const Scan& source,
                                      const Scan& target, const Transform& T_target_source,
                                      const CloudExportConfig& config = CloudExportConfig());

}  // namespace zeroreg
