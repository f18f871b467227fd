// The Open3D module (src/open3d_module/, docs/SPEED.md "Start-up"): what goes through it gives
// exactly what Open3D gives when called directly; the CLI does not link Open3D, registers frame
// pairs without the module, and names the module and where it looked when a command needs it and
// it is missing.
#include "open3d_module/open3d_module.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/io/PointCloudIO.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <open3d/pipelines/registration/Feature.h>
#include <stdlib.h>

#include <cstring>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "assets/assets_test_util.hpp"
#include "estimate/lift.hpp"
#include "features/fpfh.hpp"
#include "fuse/fuse.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing::RedkitchenDir;
using testing::RunCli;
using testing::RunCommand;

std::string CoreBinary() {
  return (std::filesystem::path(testing::CliPath()).parent_path() / "zeroreg-core").string();
}

TEST(Open3dModule, FpfhThroughTheModuleIsOpen3dsOwn) {
  const auto dataset = OpenDataset(RedkitchenDir());
  Scan scan;
  scan.views.push_back(dataset->LoadFrame(0));
  const std::vector<Eigen::Vector3d> points = ScanPoints(scan, PixelGrid{4}, 0.0, 6.0);
  FpfhParams params;  // the geometry hypothesis's: 5 cm voxels
  const FpfhCloud ours = ComputeFpfh(points, params);

  open3d::geometry::PointCloud full;
  full.points_ = points;
  const auto cloud = full.VoxelDownSample(params.voxel_m);
  cloud->EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(
      params.normal_radius_voxels * params.voxel_m, params.normal_max_nn));
  const auto feature = open3d::pipelines::registration::ComputeFPFHFeature(
      *cloud, open3d::geometry::KDTreeSearchParamHybrid(
                  params.feature_radius_voxels * params.voxel_m, params.feature_max_nn));
  ASSERT_GT(ours.points.size(), 100u);
  ASSERT_EQ(ours.points, cloud->points_);
  ASSERT_EQ(ours.features.rows(), 33);
  EXPECT_TRUE(ours.features == feature->data_);  // exactly
}

TEST(Open3dModule, PointCloudFilesRoundTripThroughTheModule) {
  const open3d_module::Api& api = open3d_module::Module();
  testing::TempDir dir;
  const std::vector<Eigen::Vector3d> points = {{0, 0, 1}, {0.5, -0.25, 2}, {1, 2, 3}};
  const std::vector<Eigen::Vector3d> colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ASSERT_TRUE(api.write_point_cloud(dir / "c.ply", points, colors, {}));
  std::vector<Eigen::Vector3d> read_points, read_colors;
  ASSERT_TRUE(api.read_point_cloud(dir / "c.ply", &read_points, &read_colors));
  EXPECT_EQ(read_points, points);
  ASSERT_EQ(read_colors.size(), colors.size());
  EXPECT_FALSE(api.read_point_cloud(dir / "missing.ply", &read_points, &read_colors));
}

// The fusion through the module against Open3D's TSDF volume fed directly: the same cloud file.
TEST(Open3dModule, FusionThroughTheModuleIsOpen3dsOwn) {
  const auto dataset = OpenDataset(RedkitchenDir());
  const std::vector<int> frames = {0, 5, 10, 15};
  FuseConfig config;
  testing::TempDir dir;
  ASSERT_TRUE(FuseFragment(*dataset, frames, config, dir / "fragment"));

  open3d::pipelines::integration::ScalableTSDFVolume volume(
      config.voxel_length_m, config.sdf_trunc_m,
      open3d::pipelines::integration::TSDFVolumeColorType::RGB8);
  Transform T_world_first = Transform::Identity();
  for (size_t k = 0; k < frames.size(); ++k) {
    const View view = dataset->LoadFrame(frames[k]);
    if (k == 0) T_world_first = *view.T_world_camera_gt;
    cv::Mat rgb;
    cv::cvtColor(view.color, rgb, cv::COLOR_BGR2RGB);
    open3d::geometry::Image color, depth;
    color.Prepare(rgb.cols, rgb.rows, 3, 1);
    depth.Prepare(rgb.cols, rgb.rows, 1, 4);
    for (int y = 0; y < rgb.rows; ++y) {
      std::memcpy(color.data_.data() + static_cast<size_t>(y) * rgb.cols * 3, rgb.ptr(y),
                  static_cast<size_t>(rgb.cols) * 3);
      std::memcpy(depth.data_.data() + static_cast<size_t>(y) * rgb.cols * 4, view.depth.ptr(y),
                  static_cast<size_t>(rgb.cols) * 4);
    }
    const auto rgbd = open3d::geometry::RGBDImage::CreateFromColorAndDepth(
        color, depth, 1.0, config.max_depth_m, false);
    const open3d::camera::PinholeCameraIntrinsic intrinsic(rgb.cols, rgb.rows, view.intrinsics.fx,
                                                           view.intrinsics.fy, view.intrinsics.cx,
                                                           view.intrinsics.cy);
    const Transform T_first_camera = T_world_first.inverse() * *view.T_world_camera_gt;
    volume.Integrate(*rgbd, intrinsic, T_first_camera.inverse().matrix());
  }
  const auto reference = volume.ExtractPointCloud()->VoxelDownSample(config.output_voxel_m);
  ASSERT_TRUE(open3d::io::WritePointCloud(dir / "reference.ply", *reference));
  const auto ours = testing::RunCommand("cmp '" + (dir / "fragment/cloud.ply") + "' '" +
                                        (dir / "reference.ply") + "'");
  EXPECT_EQ(ours.exit_code, 0) << ours.output;
  EXPECT_GT(reference->points_.size(), 10000u);
  EXPECT_TRUE(reference->HasNormals());
}

TEST(Open3dModule, SearchPathsHonourTheUsersFileAlone) {
  ::setenv("ZEROREG_OPEN3D_MODULE", "/somewhere/else/libzeroreg-open3d.so", 1);
  const std::vector<std::string> given = open3d_module::ModuleSearchPaths();
  ::unsetenv("ZEROREG_OPEN3D_MODULE");
  EXPECT_EQ(given, std::vector<std::string>{"/somewhere/else/libzeroreg-open3d.so"});
  // Otherwise beside the program first: the build folder, where the test binary is.
  const std::vector<std::string> paths = open3d_module::ModuleSearchPaths();
  ASSERT_GE(paths.size(), 2u);
  EXPECT_TRUE(std::filesystem::exists(paths.front())) << paths.front();
  EXPECT_NE(paths.front().find(open3d_module::kFileName), std::string::npos);
}

// A file that is no shared library, and a shared library that is not the module: each refused
// with what was wrong, never called.
TEST(Open3dModule, SomethingElseInItsPlaceIsRefusedWithAReason) {
  testing::TempDir dir;
  testing::WriteFile(dir / "libzeroreg-open3d.so", std::string(200, 'x'));  // > an ELF header
  Dl_info libc{};
  ASSERT_NE(::dladdr(reinterpret_cast<void*>(&::strlen), &libc), 0);
  const std::pair<std::string, std::string> cases[] = {
      {dir / "libzeroreg-open3d.so", "invalid ELF header"},
      {libc.dli_fname, "not a zeroreg Open3D module"}};
  for (const auto& [file, reason] : cases) {
    SCOPED_TRACE(file);
    const auto r =
        RunCommand("ZEROREG_OPEN3D_MODULE='" + file + "' '" + testing::CliPath() + "' fuse -d '" +
                   RedkitchenDir() + "' -f 0,20 -o '" + (dir / "fragment") + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find(file + ": "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(reason), std::string::npos) << r.output;
  }
}

TEST(Open3dModule, InfoSaysWhereTheModuleIsOrWhyItDoesNotLoad) {
  const auto found = RunCli("info");
  ASSERT_EQ(found.exit_code, 0) << found.output;
  EXPECT_NE(found.output.find("open3d module: /"), std::string::npos) << found.output;
  EXPECT_NE(found.output.find("libzeroreg-open3d.so (loads"), std::string::npos) << found.output;
  const auto missing = RunCommand("ZEROREG_OPEN3D_MODULE=/nonexistent/libzeroreg-open3d.so '" +
                                  testing::CliPath() + "' info");
  ASSERT_EQ(missing.exit_code, 0) << missing.output;
  EXPECT_NE(missing.output.find("open3d module: NOT LOADABLE"), std::string::npos)
      << missing.output;
}

TEST(Open3dModule, TheCliDoesNotLinkOpen3d) {
  // ldd lists every shared library the loader maps at start-up, transitively.
  const auto ldd = RunCommand("ldd '" + CoreBinary() + "'");
  ASSERT_EQ(ldd.exit_code, 0) << ldd.output;
  EXPECT_NE(ldd.output.find("libopencv_core"), std::string::npos) << ldd.output;
  EXPECT_EQ(ldd.output.find("Open3D"), std::string::npos) << ldd.output;
}

TEST(Open3dModule, FramePairsRegisterWithoutItAndCommandsThatNeedItSaySo) {
  const std::string missing = "/nonexistent/zeroreg-test/libzeroreg-open3d.so";
  const std::string env = "ZEROREG_OPEN3D_MODULE='" + missing + "' ";
  // The demo pair: the object level registers it, nothing of Open3D is needed.
  const auto frames = RunCommand(env + "'" + testing::CliPath() + "' register -s '" +
                                 RedkitchenDir() + "@20' -t '" + RedkitchenDir() + "@0'");
  EXPECT_EQ(frames.exit_code, 0) << frames.output;
  EXPECT_NE(frames.output.find("verdict: VALID"), std::string::npos) << frames.output;
  // Fusion needs Open3D's TSDF volume: a clear error naming the module and where it looked.
  testing::TempDir dir;
  const auto fuse = RunCommand(env + "'" + testing::CliPath() + "' fuse -d '" + RedkitchenDir() +
                               "' -f 0,20 -o '" + (dir / "fragment") + "'");
  EXPECT_NE(fuse.exit_code, 0);
  EXPECT_NE(fuse.output.find("libzeroreg-open3d.so"), std::string::npos) << fuse.output;
  EXPECT_NE(fuse.output.find(missing + ": no such file"), std::string::npos) << fuse.output;
  EXPECT_NE(fuse.output.find("ZEROREG_OPEN3D_MODULE"), std::string::npos) << fuse.output;
}

}  // namespace
}  // namespace zeroreg
