#include "synthesis/virtual_cameras.hpp"

#include <cmath>
#include <cstdio>

#include "eval/metrics.hpp"

namespace zeroreg {

bool NearCamera(const Transform& a, const Transform& b, double deg, double m) {
  const double moved = (a.topRightCorner<3, 1>() - b.topRightCorner<3, 1>()).norm();
  return moved < m && RotationErrorDeg(a, b) < deg;
}

std::vector<VirtualCamera> CamerasFromHypotheses(const std::vector<PoseHypothesis>& hypotheses,
                                                 const Scan& source, double merge_deg,
                                                 double merge_m, int max_cameras) {
  std::vector<VirtualCamera> out;
  for (const PoseHypothesis& h : hypotheses) {
    for (size_t v = 0; v < source.views.size(); ++v) {
      const Transform T = h.T_target_source * source.views[v].T_scan_camera;
      bool near = false;
      for (const VirtualCamera& kept : out) {
        near = near || (kept.source_view == static_cast<int>(v) &&
                        NearCamera(kept.T_target_camera, T, merge_deg, merge_m));
      }
      if (near) continue;
      if (max_cameras > 0 && static_cast<int>(out.size()) >= max_cameras) return out;
      out.push_back({h.name, static_cast<int>(v), T});
    }
  }
  return out;
}

Eigen::Vector3d SurfaceCentroid(const View& view, double min_m, double max_m) {
  const Intrinsics& K = view.intrinsics;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (int v = 0; v < view.depth.rows; v += 8) {
    const float* row = view.depth.ptr<float>(v);
    for (int u = 0; u < view.depth.cols; u += 8) {
      const double z = row[u];
      if (!(z >= min_m && z <= max_m)) continue;
      sum += Eigen::Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
      ++n;
    }
  }
  const Eigen::Vector3d camera = n > 0 ? Eigen::Vector3d(sum / n) : Eigen::Vector3d::Zero();
  return (view.T_scan_camera * camera.homogeneous()).head<3>();
}

std::vector<VirtualCamera> OrbitCameras(const Scan& target, const std::vector<double>& angles_deg,
                                        int source_view) {
  std::vector<VirtualCamera> out;
  for (const View& view : target.views) {
    const Eigen::Vector3d centre = SurfaceCentroid(view, 0.1, 8.0);
    // Image up is -y in OpenCV camera axes.
    const Eigen::Vector3d up = -view.T_scan_camera.block<3, 1>(0, 1);
    for (const double deg : angles_deg) {
      Transform turn = Transform::Identity();
      const Eigen::Matrix3d R = Eigen::AngleAxisd(deg * M_PI / 180.0, up).toRotationMatrix();
      turn.topLeftCorner<3, 3>() = R;
      turn.topRightCorner<3, 1>() = centre - R * centre;
      char name[48];
      std::snprintf(name, sizeof(name), "orbit %+.0f deg", deg);
      out.push_back({name, source_view, turn * view.T_scan_camera});
    }
  }
  return out;
}

}  // namespace zeroreg
