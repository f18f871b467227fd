// Coloured PLY export (src/viz/ply.hpp): files re-read with Open3D hold the right points, in the
// right colours, and the source half of registered.ply is exactly T * source.ply.
#include "viz/ply.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <open3d/geometry/PointCloud.h>
#include <open3d/io/PointCloudIO.h>
#include <filesystem>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

// A rotation of 30 deg about a tilted axis and a translation, all non-trivial.
Transform TestTransform() {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(0.4, -0.3, 1.2);
  return T;
}

// Points on a 5 cm grid (one per 1 cm voxel, so downsampling keeps them all), each coloured by
// its position.
Scan GridScan(const Eigen::Vector3d& offset, int nx, int ny, int nz) {
  Scan scan;
  for (int x = 0; x < nx; ++x) {
    for (int y = 0; y < ny; ++y) {
      for (int z = 0; z < nz; ++z) {
        scan.points.push_back(offset + 0.05 * Eigen::Vector3d(x, y, z) +
                              Eigen::Vector3d(0.005, 0.005, 0.005));  // voxel centres
        scan.colors.emplace_back(x / double(nx), y / double(ny), z / double(nz));
      }
    }
  }
  return scan;
}

class PlyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("zeroreg_ply_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static open3d::geometry::PointCloud Read(const std::string& path) {
    open3d::geometry::PointCloud cloud;
    EXPECT_TRUE(open3d::io::ReadPointCloud(path, cloud)) << path;
    return cloud;
  }
  fs::path dir_;
};

void ExpectColor(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected) {
  EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(), 0.5 / 255 + 1e-9)
      << actual.transpose() << " vs " << expected.transpose();
}

TEST_F(PlyTest, RegisteredPlyHoldsTargetThenTransformedSource) {
  const Scan source = GridScan(Eigen::Vector3d(-0.2, 0.1, 1.0), 4, 5, 3);  // 60 points
  const Scan target = GridScan(Eigen::Vector3d(0.3, -0.2, 2.0), 3, 3, 2);  // 18 points
  const Transform T = TestTransform();
  const RegisteredPlyFiles files = WriteRegisteredPly(dir_.string(), source, target, T);
  EXPECT_EQ(files.num_source, 60u);
  EXPECT_EQ(files.num_target, 18u);

  const auto registered = Read(files.registered);
  const auto source_ply = Read(files.source);
  const auto target_ply = Read(files.target);
  ASSERT_EQ(registered.points_.size(), 78u);
  ASSERT_EQ(registered.colors_.size(), 78u);
  ASSERT_EQ(source_ply.points_.size(), 60u);
  ASSERT_EQ(target_ply.points_.size(), 18u);

  for (size_t k = 0; k < 18; ++k) {
    EXPECT_LE((registered.points_[k] - target.points[k]).norm(), 1e-6);
    EXPECT_LE((target_ply.points_[k] - target.points[k]).norm(), 1e-6);
    ExpectColor(registered.colors_[k], kTargetColor);
    ExpectColor(target_ply.colors_[k], target.colors[k]);  // own colours in target.ply
  }
  for (size_t k = 0; k < 60; ++k) {
    // source.ply is the source in its own frame; registered.ply's source half is T times it.
    EXPECT_LE((source_ply.points_[k] - source.points[k]).norm(), 1e-6);
    const Eigen::Vector3d moved = (T * source.points[k].homogeneous()).head<3>();
    EXPECT_LE((registered.points_[18 + k] - moved).norm(), 1e-6) << k;
    ExpectColor(registered.colors_[18 + k], kSourceColor);
    ExpectColor(source_ply.colors_[k], source.colors[k]);
  }
}

TEST_F(PlyTest, DepthIsBackProjectedIntoTheScanFrame) {
  // An 8x6 view of a plane at 2 m; two pixels invalid, one beyond the depth range.
  View view;
  view.intrinsics = {4.0, 5.0, 3.5, 2.5, 8, 6};
  view.depth = cv::Mat(6, 8, CV_32FC1, cv::Scalar(2.0f));
  view.depth.at<float>(0, 0) = 0.0f;
  view.depth.at<float>(5, 7) = 0.0f;
  view.depth.at<float>(3, 3) = 9.0f;                            // beyond max_depth_m = 6
  view.color = cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 20, 30));  // BGR
  view.T_scan_camera = TestTransform();
  Scan scan;
  scan.views.push_back(view);

  CloudExportConfig config;
  config.voxel_m = 0;  // every pixel
  const ColoredCloud cloud = ScanGeometry(scan, kSourceColor, config);
  ASSERT_EQ(cloud.points.size(), 48u - 3u);
  // Pixel (u=1, v=0) is the first valid one: ((1 - 3.5) * 2 / 4, (0 - 2.5) * 2 / 5, 2).
  const Eigen::Vector3d camera(-1.25, -1.0, 2.0);
  EXPECT_LE((cloud.points[0] - (TestTransform() * camera.homogeneous()).head<3>()).norm(), 1e-12);
  EXPECT_LE((cloud.colors[0] - Eigen::Vector3d(30, 20, 10) / 255.0).norm(), 1e-12);  // RGB

  // At 1 cm the 45 points, 0.5 m apart on the plane, stay distinct; at 10 m they become one.
  config.voxel_m = 0.01;
  EXPECT_EQ(ScanGeometry(scan, kSourceColor, config).points.size(), 45u);
  config.voxel_m = 10.0;
  EXPECT_LE(ScanGeometry(scan, kSourceColor, config).points.size(), 8u);  // voxel boundaries
  // Without scan colours every point takes the origin colour.
  config.use_scan_colors = false;
  for (const auto& c : ScanGeometry(scan, kSourceColor, config).colors) {
    EXPECT_LE((c - kSourceColor).norm(), 1e-12);  // a mean of equal colours
  }
}

TEST(PlyVoxel, AveragesPointsAndColoursPerVoxelInFirstSeenOrder) {
  ColoredCloud cloud;
  cloud.points = {{0.012, 0.0, 0.0}, {0.001, 0.001, 0.001}, {0.018, 0.004, 0.002}};
  cloud.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const ColoredCloud down = VoxelDownsample(cloud, 0.01);
  ASSERT_EQ(down.points.size(), 2u);
  EXPECT_LE((down.points[0] - Eigen::Vector3d(0.015, 0.002, 0.001)).norm(), 1e-12);
  EXPECT_LE((down.colors[0] - Eigen::Vector3d(0.5, 0, 0.5)).norm(), 1e-12);
  EXPECT_LE((down.points[1] - Eigen::Vector3d(0.001, 0.001, 0.001)).norm(), 1e-12);
}

TEST_F(PlyTest, WriteErrorsNameTheFile) {
  ColoredCloud bad;
  bad.points = {{0, 0, 0}};
  try {
    WritePly((dir_ / "bad.ply").string(), bad);
    FAIL() << "no error for points without colours";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one colour per point"), std::string::npos) << e.what();
  }
  ColoredCloud good;
  good.points = {{0, 0, 0}};
  good.colors = {{0, 0, 0}};
  EXPECT_THROW(WritePly((dir_ / "no-such-folder" / "x.ply").string(), good), InputError);
}

// A full disk (/dev/full, through a link in the test's folder) gives the system's reason, and a
// PLY that was there stays whole: the new one is written beside it and renamed over it.
TEST_F(PlyTest, FullDiskSaysWhyAndKeepsThePreviousFile) {
  ColoredCloud cloud;
  cloud.points = {{0, 0, 0}, {1, 0, 0}};
  cloud.colors = {{0, 0, 0}, {1, 1, 1}};
  fs::create_directories(dir_);
  const std::string kept = (dir_ / "kept.ply").string();
  WritePly(kept, cloud);
  const auto size = fs::file_size(kept);
  cloud.points.resize(1000, Eigen::Vector3d(0.5, 0.5, 0.5));
  cloud.colors.resize(1000, Eigen::Vector3d(0.5, 0.5, 0.5));
  WritePly(kept, cloud);
  EXPECT_GT(fs::file_size(kept), size);
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename(), "kept.ply") << "a temporary file was left behind";
  }
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "/dev/full is absent";
  const std::string full = (dir_ / "full.ply").string();
  fs::create_symlink("/dev/full", full);
  try {
    WritePly(full, cloud);
    FAIL() << "no error writing to a full disk";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("full.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

}  // namespace
}  // namespace zeroreg
