// Optional refinement of a registration by coarse-to-fine point-to-plane ICP on the scans'
// geometry. Our own Gauss-Newton loop on Open3D's normals and our own k-d tree
// (point_kd_tree.hpp), with serial reductions, so the result is a function of the input only
// (Open3D's ICP sums in parallel threads).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct IcpResult {
  Transform T_target_source = Transform::Identity();
  double fitness = 0.0;  // last stage: fraction of source points with a target point in the gate
  double rmse = 0.0;     // metres, over those points
  int iterations = 0;    // over all stages
};

// One ICP stage: points thinned to one per voxel_m cube, closest-point pairs farther apart than
// max_distance_m ignored, at most `iterations` Gauss-Newton steps.
struct IcpStage {
  double voxel_m = 0.02;
  double max_distance_m = 0.05;
  int iterations = 30;
  // Total weight of the IcpAnchors in this stage's gate relative to all its closest-point pairs
  // (0 = not used).
  double anchor_weight = 0.0;
  // > 0: each closest-point pair weighs 1 / (sigma(d_s)^2 + sigma(d_t)^2), with the axial depth
  // noise sigma(d) = depth_noise_at_1m_m * d^depth_noise_exponent of its two depth readings
  // (DepthModel); 0: equal weights.
  double depth_noise_at_1m_m = 0.0;
  double depth_noise_exponent = 2.0;
};

// Image correspondences that ICP must keep agreeing with (the estimate's RANSAC inliers): each pair
// adds the 3D residual T * source - target to the fit, gated like the closest-point pairs of each
// stage. They anchor the motions the geometry leaves weak (sliding along a floor or a wall), where
// plain ICP follows the bias of pairs at the fringe of the overlap.
struct IcpAnchors {
  std::vector<Eigen::Vector3d> source, target;  // parallel
};

// The coarse, fine and final stages of RefineConfig, in order, weighted by the depth model's noise.
std::vector<IcpStage> IcpSchedule(const RefineConfig& config, const DepthModel& depth);

// A scan's points thinned to each resolution of an ICP schedule, with normals and a k-d tree per
// resolution: everything ICP needs of one scan, in either role (source: the thinned points; target:
// points, normals, tree). Built once per scan (Pipeline::Prepare) and shared read-only by every
// registration the scan is in; copies share the data.
class IcpGeometry {
 public:
  IcpGeometry();
  ~IcpGeometry();
  IcpGeometry(const IcpGeometry&);
  IcpGeometry& operator=(const IcpGeometry&);
  // Thins `points` (raw, scan frame) to one point per voxel for every distinct voxel size of
  // `stages` that runs. What only a target needs (normals from 30 neighbours within 3 voxels, the
  // k-d tree) is made now when `as_target`, else on first use as a target (once, thread-safe):
  // a scan known to be only a source skips it. `camera_depth` (parallel to `points`, or empty when
  // unknown, as for a fused cloud) is each point's depth reading, averaged per voxel like the
  // points, for the depth-noise weights (IcpStage::depth_noise_at_1m_m).
  IcpGeometry(const std::vector<Eigen::Vector3d>& points, const std::vector<IcpStage>& stages,
              bool as_target = true, const std::vector<double>& camera_depth = {});
  // Points at the resolution voxel_m (0 when that resolution was not built).
  size_t NumPoints(double voxel_m) const;
  size_t MemoryBytes() const;  // approximate heap use

  struct Level;  // Open3D types stay out of this header

 private:
  friend IcpResult RefinePointToPlane(const IcpGeometry&, const IcpGeometry&, const Transform&,
                                      const std::vector<IcpStage>&, const IcpAnchors&, int);
  std::vector<std::shared_ptr<const Level>> levels_;  // one per distinct voxel size, in order
};

// The ICP geometry of a scan as the pipeline refines with it: every pixel_stride-th depth pixel
// of its views (RefineConfig::pixel_stride; 0 = every other pixel at 640 px wide, following the
// image size) with its depth reading (the stages thin to 2 cm voxels or coarser), or its fused
// point cloud without readings.
IcpGeometry ScanIcpGeometry(const Scan& scan, const std::vector<IcpStage>& stages,
                            bool as_target = true, int pixel_stride = 0);

// Point-to-plane ICP from `initial` through `stages` (which must be those the geometries were
// built for). The closest-point search of each iteration runs on `threads` threads; the sums are
// reduced serially in point order, so the result is bit-identical for any thread count.
IcpResult RefinePointToPlane(const IcpGeometry& source, const IcpGeometry& target,
                             const Transform& initial, const std::vector<IcpStage>& stages,
                             const IcpAnchors& anchors = IcpAnchors(), int threads = 1);

// The same on raw (not yet thinned) points in the source and target frames: builds both
// geometries first.
IcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const Transform& initial,
                             const std::vector<IcpStage>& stages,
                             const IcpAnchors& anchors = IcpAnchors(), int threads = 1);

}  // namespace zeroreg
