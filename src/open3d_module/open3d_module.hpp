// Everything zeroreg takes from Open3D, behind one table of functions in a module of its own,
// libzeroreg-open3d.so, loaded the first time one of them is called (docs/SPEED.md, "Start-up").
//
// Why: Open3D 0.16 brings about 100 shared libraries (VTK, filament, embree, ...) that the dynamic
// loader maps and relocates, eagerly (Debian links them with BIND_NOW), before main: a fifth of
// a frame-pair registration's wall time (docs/SPEED.md, "Start-up"). A frame pair usually needs
// none of it (ICP's clouds, normals and k-d trees are zeroreg's own), so only the processes that
// need it pay for it. The module is needed by the geometry hypothesis (FPFH), point
// cloud files (.ply of fused fragments), TSDF fusion and the FPFH + RANSAC baseline.
//
// The interface is plain data only (std containers, Eigen, raw image rows), so the module needs
// no symbol of zeroreg's and the same file serves the CLI, the Python module and the tests.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace zeroreg::open3d_module {

// Bumped whenever a signature or struct below changes: a module built from other sources is
// refused with a message instead of being called with the wrong layout.
constexpr int kAbiVersion = 2;

// FPFH (Rusu et al., ICRA 2009) of a cloud: voxel down-sampling, normals (hybrid search), then
// one 33-bin histogram per kept point (features/fpfh.hpp names these zeroreg::FpfhParams and
// zeroreg::FpfhCloud).
struct FpfhParams {
  double voxel_m = 0.05;               // voxel down-sampling
  double normal_radius_voxels = 2.0;   // normals: hybrid search radius, in voxels
  int normal_max_nn = 30;              // normals: at most this many neighbours
  double feature_radius_voxels = 5.0;  // FPFH: hybrid search radius, in voxels
  int feature_max_nn = 100;            // FPFH: at most this many neighbours
};
struct FpfhCloud {
  std::vector<Eigen::Vector3d> points;  // the down-sampled points
  Eigen::MatrixXd features;             // 33 x points.size(), a column per point
};

// Open3D's RegistrationRANSACBasedOnFeatureMatching (the FPFH + RANSAC baseline of `zeroreg eval
// --method fpfh`) with point-to-point estimation, 3-point samples, the edge-length and distance
// checkers, seeded with `seed`.
struct FeatureRansacRequest {
  bool mutual_filter = false;
  double max_distance_m = 0.075;
  double edge_length_similarity = 0.9;
  int max_iterations = 100000;
  double confidence = 0.999;
  int seed = 0;
};
struct FeatureRansacResult {
  Eigen::Matrix4d T_target_source = Eigen::Matrix4d::Identity();
  double fitness = 0.0;
  int num_inliers = 0;
  // Each source point with its nearest target point in feature space (-1: none): the putative
  // correspondences RANSAC samples from when the mutual filter is off.
  std::vector<int> nearest_target;
};

// One RGB-D frame for TSDF integration: 8-bit RGB rows and float depth in metres, same size.
struct RgbdFrame {
  int width = 0, height = 0;
  const std::uint8_t* rgb = nullptr;  // height rows of width * 3 bytes, `rgb_step` bytes apart
  std::size_t rgb_step = 0;
  const float* depth = nullptr;  // height rows of width floats, `depth_step` bytes apart
  std::size_t depth_step = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix4d T_camera_volume = Eigen::Matrix4d::Identity();  // volume frame -> camera
};

// Open3D's point-to-plane ICP (RegistrationICP with TransformationEstimationPointToPlane) from
// `init`, normals of the target estimated with a hybrid search, and the 6x6 information matrix of
// the result (GetInformationMatrixFromPointClouds): the pair edge of Open3D's multiway
// registration recipe.
struct IcpRequest {
  double max_distance_m = 0.075;
  double normal_radius_m = 0.1;
  int normal_max_nn = 30;
  int max_iterations = 30;
  Eigen::Matrix4d init = Eigen::Matrix4d::Identity();
};
struct IcpResult {
  Eigen::Matrix4d T_target_source = Eigen::Matrix4d::Identity();
  double fitness = 0.0;      // fraction of source points within max_distance_m of the target
  double inlier_rmse = 0.0;  // metres
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

// A pose graph for Open3D's GlobalOptimization (Levenberg-Marquardt with the line process of
// Choi et al., CVPR 2015). Nodes are world_from_node poses; an edge's T_target_source maps the
// source node's frame into the target node's. Uncertain edges (loop closures) get a line-process
// weight, returned in `confidence`, and are pruned below the threshold (`pruned` set).
struct PoseGraphEdge {
  int source = 0, target = 0;
  Eigen::Matrix4d T_target_source = Eigen::Matrix4d::Identity();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
  bool uncertain = false;
  double confidence = 1.0;
  bool pruned = false;
};
struct PoseGraphOptions {
  double max_correspondence_distance_m = 0.075;
  double edge_prune_threshold = 0.25;
  double preference_loop_closure = 1.0;
  int reference_node = 0;
};

// What both sides' compilers made of the types above: the module must agree with its host on the
// library ABI of std::string and std::vector and on Eigen's alignment, which the version number
// alone does not say.
constexpr std::size_t kLayout =
    sizeof(std::string) * 1000003u + sizeof(std::vector<double>) * 10007u +
    alignof(Eigen::Matrix4d) * 101u + sizeof(Eigen::MatrixXd) + sizeof(RgbdFrame) * 7u +
    sizeof(FeatureRansacResult) * 13u + sizeof(IcpResult) * 17u + sizeof(PoseGraphEdge) * 19u;

struct Api {
  int abi_version = 0;
  std::size_t layout = 0;  // kLayout of the module's build
  void (*compute_fpfh)(const std::vector<Eigen::Vector3d>& points, const FpfhParams& params,
                       FpfhCloud* out) = nullptr;
  void (*feature_ransac)(const FpfhCloud& source, const FpfhCloud& target,
                         const FeatureRansacRequest& request, FeatureRansacResult* out) = nullptr;
  // Point cloud files in any format Open3D reads or writes (by extension); false on failure.
  // Colours (RGB in [0, 1]) and normals may be empty, or one per point.
  bool (*read_point_cloud)(const std::string& path, std::vector<Eigen::Vector3d>* points,
                           std::vector<Eigen::Vector3d>* colors) = nullptr;
  bool (*write_point_cloud)(const std::string& path, const std::vector<Eigen::Vector3d>& points,
                            const std::vector<Eigen::Vector3d>& colors,
                            const std::vector<Eigen::Vector3d>& normals) = nullptr;
  // A scalable TSDF volume with RGB colour: made, fed frames, turned into a coloured cloud
  // (down-sampled to output_voxel_m when > 0), freed.
  void* (*tsdf_create)(double voxel_length_m, double sdf_trunc_m) = nullptr;
  void (*tsdf_integrate)(void* volume, const RgbdFrame& frame, double max_depth_m) = nullptr;
  void (*tsdf_extract)(void* volume, double output_voxel_m, std::vector<Eigen::Vector3d>* points,
                       std::vector<Eigen::Vector3d>* colors,
                       std::vector<Eigen::Vector3d>* normals) = nullptr;
  void (*tsdf_destroy)(void* volume) = nullptr;
  void (*point_to_plane_icp)(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target, const IcpRequest& request,
                             IcpResult* out) = nullptr;
  // Optimises `world_from_node` in place; edges get their confidence and pruned flag.
  void (*optimize_pose_graph)(std::vector<Eigen::Matrix4d>* world_from_node,
                              std::vector<PoseGraphEdge>* edges,
                              const PoseGraphOptions& options) = nullptr;
};

// The module's one exported symbol.
constexpr const char* kEntryPoint = "zeroreg_open3d_module_api";
constexpr const char* kFileName = "libzeroreg-open3d.so";

// The loaded module, loaded on the first call (thread-safe). Looked for: the file
// $ZEROREG_OPEN3D_MODULE when set (only there); otherwise, in order, libzeroreg-open3d.so beside
// the program or shared object that holds this code (the build folder, the Python package);
// ../lib/zeroreg/ from there (an installed bin/); the configured install prefix's lib/zeroreg/; the
// build folder zeroreg was compiled in. Throws InputError naming every place looked in and what
// each said when none loads.
const Api& Module();

// The file Module() loaded (loading it first; throws as Module() does). For `zeroreg info`.
std::string LoadedModulePath();

// Where Module() looks, in order (for messages and tests).
std::vector<std::string> ModuleSearchPaths();

}  // namespace zeroreg::open3d_module
