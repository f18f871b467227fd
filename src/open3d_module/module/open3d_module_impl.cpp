// libzeroreg-open3d.so: the Open3D side of src/open3d_module/open3d_module.hpp. Built as its own
// shared module (not part of libzeroreg), linking Open3D alone; it uses no zeroreg symbol, so it
// loads into any program or Python module that carries zeroreg.
#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/io/PointCloudIO.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <open3d/pipelines/registration/CorrespondenceChecker.h>
#include <open3d/pipelines/registration/Feature.h>
#include <open3d/pipelines/registration/GlobalOptimization.h>
#include <open3d/pipelines/registration/PoseGraph.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/utility/Logging.h>
#include <open3d/utility/Random.h>

#include <cstring>
#include <mutex>

#include "open3d_module/open3d_module.hpp"

namespace {

namespace api = zeroreg::open3d_module;
namespace reg = open3d::pipelines::registration;
using open3d::geometry::PointCloud;

// Open3D prints warnings such as "clamped color value" on stdout; they would bury progress lines
// and make stdout differ from run to run. Errors still show.
void QuietOnce() {
  static std::once_flag once;
  std::call_once(
      once, [] { open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error); });
}

void ComputeFpfh(const std::vector<Eigen::Vector3d>& points, const api::FpfhParams& p,
                 api::FpfhCloud* out) {
  QuietOnce();
  PointCloud full;
  full.points_ = points;
  const std::shared_ptr<PointCloud> cloud = full.VoxelDownSample(p.voxel_m);
  cloud->EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(
      p.normal_radius_voxels * p.voxel_m, p.normal_max_nn));
  const std::shared_ptr<reg::Feature> feature =
      reg::ComputeFPFHFeature(*cloud, open3d::geometry::KDTreeSearchParamHybrid(
                                          p.feature_radius_voxels * p.voxel_m, p.feature_max_nn));
  out->points = std::move(cloud->points_);
  out->features = std::move(feature->data_);
}

// Open3D's RNG is one global engine: seeding it and running RANSAC must not interleave with
// another thread's RANSAC, or neither result would depend on its seed alone.
std::mutex& RandomMutex() {
  static std::mutex mutex;
  return mutex;
}

void FeatureRansac(const api::FpfhCloud& source, const api::FpfhCloud& target,
                   const api::FeatureRansacRequest& r, api::FeatureRansacResult* out) {
  QuietOnce();
  PointCloud src, tgt;
  src.points_ = source.points;
  tgt.points_ = target.points;
  reg::Feature src_feature, tgt_feature;
  src_feature.data_ = source.features;
  tgt_feature.data_ = target.features;
  out->nearest_target.assign(source.points.size(), -1);
  open3d::geometry::KDTreeFlann feature_tree(tgt_feature);
  std::vector<int> index(1);
  std::vector<double> distance2(1);
  for (size_t s = 0; s < source.points.size(); ++s) {
    const Eigen::VectorXd query = src_feature.data_.col(static_cast<Eigen::Index>(s));
    if (feature_tree.SearchKNN(query, 1, index, distance2) >= 1) out->nearest_target[s] = index[0];
  }
  reg::CorrespondenceCheckerBasedOnEdgeLength edge_checker(r.edge_length_similarity);
  reg::CorrespondenceCheckerBasedOnDistance distance_checker(r.max_distance_m);
  reg::RegistrationResult result;
  {
    std::lock_guard<std::mutex> lock(RandomMutex());
    open3d::utility::random::Seed(r.seed);
    result = reg::RegistrationRANSACBasedOnFeatureMatching(
        src, tgt, src_feature, tgt_feature, r.mutual_filter, r.max_distance_m,
        reg::TransformationEstimationPointToPoint(false), /*ransac_n=*/3,
        {edge_checker, distance_checker},
        reg::RANSACConvergenceCriteria(r.max_iterations, r.confidence));
  }
  out->T_target_source = result.transformation_;
  out->fitness = result.fitness_;
  out->num_inliers = static_cast<int>(result.correspondence_set_.size());
}

bool ReadPointCloud(const std::string& path, std::vector<Eigen::Vector3d>* points,
                    std::vector<Eigen::Vector3d>* colors) {
  QuietOnce();
  PointCloud cloud;
  open3d::io::ReadPointCloudOption option;
  option.print_progress = false;
  if (!open3d::io::ReadPointCloud(path, cloud, option)) return false;
  *points = std::move(cloud.points_);
  *colors = std::move(cloud.colors_);
  return true;
}

bool WritePointCloud(const std::string& path, const std::vector<Eigen::Vector3d>& points,
                     const std::vector<Eigen::Vector3d>& colors,
                     const std::vector<Eigen::Vector3d>& normals) {
  QuietOnce();
  PointCloud cloud;
  cloud.points_ = points;
  cloud.colors_ = colors;
  cloud.normals_ = normals;
  return open3d::io::WritePointCloud(path, cloud);
}

using Volume = open3d::pipelines::integration::ScalableTSDFVolume;

void* TsdfCreate(double voxel_length_m, double sdf_trunc_m) {
  QuietOnce();
  return new Volume(voxel_length_m, sdf_trunc_m,
                    open3d::pipelines::integration::TSDFVolumeColorType::RGB8);
}

void TsdfIntegrate(void* volume, const api::RgbdFrame& f, double max_depth_m) {
  open3d::geometry::Image color, depth;
  color.Prepare(f.width, f.height, 3, 1);
  depth.Prepare(f.width, f.height, 1, 4);
  const size_t color_row = static_cast<size_t>(f.width) * 3, depth_row = color_row / 3 * 4;
  for (int y = 0; y < f.height; ++y) {
    std::memcpy(color.data_.data() + static_cast<size_t>(y) * color_row,
                f.rgb + static_cast<size_t>(y) * f.rgb_step, color_row);
    std::memcpy(
        depth.data_.data() + static_cast<size_t>(y) * depth_row,
        reinterpret_cast<const std::uint8_t*>(f.depth) + static_cast<size_t>(y) * f.depth_step,
        depth_row);
  }
  const auto rgbd = open3d::geometry::RGBDImage::CreateFromColorAndDepth(
      color, depth, /*depth_scale=*/1.0, max_depth_m, /*convert_rgb_to_intensity=*/false);
  const open3d::camera::PinholeCameraIntrinsic intrinsic(f.width, f.height, f.fx, f.fy, f.cx, f.cy);
  static_cast<Volume*>(volume)->Integrate(*rgbd, intrinsic, f.T_camera_volume);
}

void TsdfExtract(void* volume, double output_voxel_m, std::vector<Eigen::Vector3d>* points,
                 std::vector<Eigen::Vector3d>* colors, std::vector<Eigen::Vector3d>* normals) {
  std::shared_ptr<PointCloud> cloud = static_cast<Volume*>(volume)->ExtractPointCloud();
  if (output_voxel_m > 0) cloud = cloud->VoxelDownSample(output_voxel_m);
  *points = std::move(cloud->points_);
  *colors = std::move(cloud->colors_);
  *normals = std::move(cloud->normals_);
}

void TsdfDestroy(void* volume) { delete static_cast<Volume*>(volume); }

void PointToPlaneIcp(const std::vector<Eigen::Vector3d>& source,
                     const std::vector<Eigen::Vector3d>& target, const api::IcpRequest& r,
                     api::IcpResult* out) {
  QuietOnce();
  PointCloud src, tgt;
  src.points_ = source;
  tgt.points_ = target;
  tgt.EstimateNormals(
      open3d::geometry::KDTreeSearchParamHybrid(r.normal_radius_m, r.normal_max_nn));
  const reg::RegistrationResult result = reg::RegistrationICP(
      src, tgt, r.max_distance_m, r.init, reg::TransformationEstimationPointToPlane(),
      reg::ICPConvergenceCriteria(1e-6, 1e-6, r.max_iterations));
  out->T_target_source = result.transformation_;
  out->fitness = result.fitness_;
  out->inlier_rmse = result.inlier_rmse_;
  out->information =
      reg::GetInformationMatrixFromPointClouds(src, tgt, r.max_distance_m, result.transformation_);
}

void OptimizePoseGraph(std::vector<Eigen::Matrix4d>* world_from_node,
                       std::vector<api::PoseGraphEdge>* edges, const api::PoseGraphOptions& o) {
  QuietOnce();
  reg::PoseGraph graph;
  for (const Eigen::Matrix4d& pose : *world_from_node) graph.nodes_.emplace_back(pose);
  for (const api::PoseGraphEdge& e : *edges) {
    graph.edges_.emplace_back(e.source, e.target, e.T_target_source, e.information, e.uncertain,
                              e.confidence);
  }
  reg::GlobalOptimization(
      graph, reg::GlobalOptimizationLevenbergMarquardt(),
      reg::GlobalOptimizationConvergenceCriteria(),
      reg::GlobalOptimizationOption(o.max_correspondence_distance_m, o.edge_prune_threshold,
                                    o.preference_loop_closure, o.reference_node));
  for (size_t n = 0; n < world_from_node->size(); ++n)
    (*world_from_node)[n] = graph.nodes_[n].pose_;
  // GlobalOptimization removes the pruned edges and keeps the others in order, with their
  // line-process weight in confidence_: match them back by their end nodes.
  size_t kept = 0;
  for (api::PoseGraphEdge& e : *edges) {
    if (kept < graph.edges_.size() && graph.edges_[kept].source_node_id_ == e.source &&
        graph.edges_[kept].target_node_id_ == e.target) {
      e.confidence = graph.edges_[kept].confidence_;
      e.pruned = false;
      ++kept;
    } else {
      e.pruned = true;
      e.confidence = 0.0;
    }
  }
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const api::Api* zeroreg_open3d_module_api() {
  static const api::Api table = [] {
    api::Api t;
    t.abi_version = api::kAbiVersion;
    t.layout = api::kLayout;
    t.compute_fpfh = ComputeFpfh;
    t.feature_ransac = FeatureRansac;
    t.read_point_cloud = ReadPointCloud;
    t.write_point_cloud = WritePointCloud;
    t.tsdf_create = TsdfCreate;
    t.tsdf_integrate = TsdfIntegrate;
    t.tsdf_extract = TsdfExtract;
    t.tsdf_destroy = TsdfDestroy;
    t.point_to_plane_icp = PointToPlaneIcp;
    t.optimize_pose_graph = OptimizePoseGraph;
    return t;
  }();
  return &table;
}
