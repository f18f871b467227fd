// TUM, ScanNet and 3DMatch layouts and scan descriptors built in a temp folder with exactly known
// contents.
#include <gtest/gtest.h>

#include <open3d/geometry/PointCloud.h>
#include <open3d/io/PointCloudIO.h>
#include <cmath>

#include "io/io_test_util.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing_io::MatrixText;
using testing_io::SomePose;
using testing_io::TempDir;
using testing_io::WriteColor;
using testing_io::WriteDepth;
using testing_io::WriteText;

// Every pixel of a CV_32FC1 image equals `value` (float).
void ExpectUniformDepth(const cv::Mat& depth, float value) {
  double lo = 0, hi = 0;
  cv::minMaxLoc(depth, &lo, &hi);
  EXPECT_FLOAT_EQ(static_cast<float>(lo), value);
  EXPECT_FLOAT_EQ(static_cast<float>(hi), value);
}

// rgb at 1.000, 1.033, 1.100, 1.133 s; depth at 1.010, 1.040, 1.060, 1.150 s. Associations within
// 0.02 s: 1.000-1.010, 1.033-1.040 (not 1.060), 1.100 has none (dropped), 1.133-1.150.
// Ground truth at 1.005 (-> rgb 1.000) and 1.140 (-> rgb 1.133); rgb 1.033 gets none.
void WriteTum(const TempDir& dir) {
  const struct {
    const char* name;
    uint16_t raw;
  } depths[] = {{"depth/1.010.png", 5000},
                {"depth/1.040.png", 10000},
                {"depth/1.060.png", 7500},
                {"depth/1.150.png", 2500}};
  // 640x480: TUM's intrinsics put the principal point near (320, 240), which must lie in the image.
  for (const auto& d : depths) WriteDepth(dir.File(d.name), 640, 480, d.raw);
  for (const char* name : {"rgb/1.000.png", "rgb/1.033.png", "rgb/1.100.png", "rgb/1.133.png"}) {
    WriteColor(dir.File(name), 640, 480);
  }
  WriteText(
      dir.File("rgb.txt"),
      "# color images\n# file: 'rgbd_dataset_test.bag'\n# timestamp filename\n"
      "1.000 rgb/1.000.png\n1.033 rgb/1.033.png\n\n1.100 rgb/1.100.png\n1.133 rgb/1.133.png\n");
  WriteText(dir.File("depth.txt"),
            "# depth maps\n1.060 depth/1.060.png\n1.010 depth/1.010.png\n1.040 depth/1.040.png\n"
            "1.150 depth/1.150.png\n");
  // 90 degrees about z: q = (0, 0, sin 45, cos 45).
  WriteText(dir.File("groundtruth.txt"),
            "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
            "1.005 1 2 3 0 0 0.70710678118654752 0.70710678118654752\n"
            "1.140 -1 0.5 0 0 0 0 1\n");
}

TEST(IoTum, AssociationDepthScaleAndPoses) {
  TempDir dir;
  WriteTum(dir);
  const auto dataset = OpenDataset(dir.path().string());
  EXPECT_EQ(dataset->layout(), DatasetLayout::kTum);
  EXPECT_EQ(dataset->FrameIds(), (std::vector<int>{0, 1, 2}));

  const View f0 = dataset->LoadFrame(0);
  ExpectUniformDepth(f0.depth, 1.0f);  // 5000 / 5000
  ASSERT_TRUE(f0.T_world_camera_gt.has_value());
  Transform expected = Transform::Identity();
  expected.topLeftCorner<3, 3>() << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  expected.topRightCorner<3, 1>() << 1, 2, 3;
  EXPECT_LT((*f0.T_world_camera_gt - expected).cwiseAbs().maxCoeff(), 1e-12);

  const View f1 = dataset->LoadFrame(1);
  ExpectUniformDepth(f1.depth, 2.0f);  // nearest depth is 1.040 (10000), not 1.060
  EXPECT_FALSE(f1.T_world_camera_gt.has_value());

  const View f2 = dataset->LoadFrame(2);
  ExpectUniformDepth(f2.depth, 0.5f);
  ASSERT_TRUE(f2.T_world_camera_gt.has_value());
  EXPECT_TRUE((f2.T_world_camera_gt->topLeftCorner<3, 3>().isIdentity(1e-12)));
  EXPECT_EQ(Eigen::Vector3d(f2.T_world_camera_gt->topRightCorner<3, 1>()),
            Eigen::Vector3d(-1, 0.5, 0));

  // No intrinsics file: TUM's ROS default.
  EXPECT_EQ(f0.intrinsics.fx, 525.0);
  EXPECT_EQ(f0.intrinsics.fy, 525.0);
  EXPECT_EQ(f0.intrinsics.cx, 319.5);
  EXPECT_EQ(f0.intrinsics.cy, 239.5);
  EXPECT_EQ(f0.intrinsics.width, 640);
  EXPECT_EQ(f0.intrinsics.height, 480);

  // DIR@N goes through the same dataset.
  const Scan scan = LoadScan(dir.path().string() + "@2");
  ASSERT_EQ(scan.views.size(), 1u);
  ExpectUniformDepth(scan.views[0].depth, 0.5f);
  EXPECT_EQ(scan.T_world_scan_gt, f2.T_world_camera_gt);
}

TEST(IoTum, IntrinsicsFileAndDepthScaleOverride) {
  TempDir dir;
  WriteTum(dir);
  WriteText(dir.File("intrinsics.txt"), "517.3 0 318.6\n0 516.5 255.3\n0 0 1\n");
  DatasetOptions options;
  options.depth_scale = 1000.0;
  const View f0 = OpenDataset(dir.path().string(), options)->LoadFrame(0);
  EXPECT_EQ(f0.intrinsics.fx, 517.3);
  EXPECT_EQ(f0.intrinsics.fy, 516.5);
  EXPECT_EQ(f0.intrinsics.cx, 318.6);
  EXPECT_EQ(f0.intrinsics.cy, 255.3);
  ExpectUniformDepth(f0.depth, 5.0f);  // 5000 / 1000
}

// SensReader export: colour 1280x960 (stands for 1296x968), depth 640x480, 4x4 depth intrinsics,
// frame 1 has an invalid (-inf) pose.
void WriteScanNet(const TempDir& dir) {
  WriteColor(dir.File("color/0.jpg"), 1280, 960, cv::Scalar(40, 100, 220));
  WriteColor(dir.File("color/1.jpg"), 1280, 960);
  WriteColor(dir.File("color/10.jpg"), 1280, 960);
  WriteDepth(dir.File("depth/0.png"), 640, 480, 1500);
  WriteDepth(dir.File("depth/1.png"), 640, 480, 700);
  WriteDepth(dir.File("depth/10.png"), 640, 480, 2000);
  WriteText(dir.File("pose/0.txt"), MatrixText(SomePose()));
  std::string inf;
  for (int k = 0; k < 16; ++k) inf += (k % 4 == 3) ? "-inf\n" : "-inf ";
  WriteText(dir.File("pose/1.txt"), inf);
  WriteText(dir.File("intrinsic/intrinsic_depth.txt"),
            "577.590698 0.000000 318.905426 0.000000\n0.000000 578.729797 242.683609 0.000000\n"
            "0.000000 0.000000 1.000000 0.000000\n0.000000 0.000000 0.000000 1.000000\n");
  WriteText(dir.File("intrinsic/intrinsic_color.txt"),
            "1170.187988 0.000000 647.750000 0.000000\n0.000000 1170.187988 483.750000 0.000000\n"
            "0.000000 0.000000 1.000000 0.000000\n0.000000 0.000000 0.000000 1.000000\n");
}

TEST(IoScanNet, ResizesColourUsesDepthIntrinsicsAndPoses) {
  TempDir dir;
  WriteScanNet(dir);
  const auto dataset = OpenDataset(dir.path().string());
  EXPECT_EQ(dataset->layout(), DatasetLayout::kScanNet);
  EXPECT_EQ(dataset->FrameIds(), (std::vector<int>{0, 1, 10}));

  const View f0 = dataset->LoadFrame(0);
  EXPECT_EQ(f0.color.size(), cv::Size(640, 480));
  EXPECT_EQ(f0.color.type(), CV_8UC3);
  const cv::Vec3b pixel = f0.color.at<cv::Vec3b>(1, 2);
  EXPECT_NEAR(pixel[0], 40, 3);  // uniform colour survives JPEG + INTER_AREA
  EXPECT_NEAR(pixel[1], 100, 3);
  EXPECT_NEAR(pixel[2], 220, 3);
  ExpectUniformDepth(f0.depth, 1.5f);
  EXPECT_EQ(f0.intrinsics.fx, 577.590698);
  EXPECT_EQ(f0.intrinsics.fy, 578.729797);
  EXPECT_EQ(f0.intrinsics.cx, 318.905426);
  EXPECT_EQ(f0.intrinsics.cy, 242.683609);
  EXPECT_EQ(f0.intrinsics.width, 640);
  ASSERT_TRUE(f0.T_world_camera_gt.has_value());
  EXPECT_LT((*f0.T_world_camera_gt - SomePose()).cwiseAbs().maxCoeff(), 1e-15);

  const View f1 = dataset->LoadFrame(1);
  ExpectUniformDepth(f1.depth, 0.7f);
  EXPECT_FALSE(f1.T_world_camera_gt.has_value());  // -inf pose
  const View f10 = dataset->LoadFrame(10);
  ExpectUniformDepth(f10.depth, 2.0f);
  EXPECT_FALSE(f10.T_world_camera_gt.has_value());  // no pose file
}

TEST(IoThreeDMatch, IntrinsicsBesideFramesAndPngColour) {
  TempDir dir;
  WriteColor(dir.File("seq/frame-000007.color.png"), 4, 3);
  WriteDepth(dir.File("seq/frame-000007.depth.png"), 4, 3, 65535);
  // One valid pixel among 65535s: 65535 becomes 0, the rest in metres.
  cv::Mat raw(3, 4, CV_16UC1, cv::Scalar(65535));
  raw.at<uint16_t>(2, 3) = 1234;
  ASSERT_TRUE(cv::imwrite(dir.File("seq/frame-000007.depth.png"), raw));
  WriteText(dir.File("seq/camera-intrinsics.txt"), "100 0 2\n0 101 1.5\n0 0 1\n");
  const auto dataset = OpenDataset(dir.path().string() + "/seq");
  EXPECT_EQ(dataset->FrameIds(), std::vector<int>{7});
  const View view = dataset->LoadFrame(7);
  EXPECT_FALSE(view.T_world_camera_gt.has_value());
  EXPECT_EQ(view.intrinsics.fy, 101.0);
  EXPECT_EQ(cv::countNonZero(view.depth), 1);
  EXPECT_FLOAT_EQ(view.depth.at<float>(2, 3), 1.234f);
}

// ---- scan descriptors
// ----------------------------------------------------------------------------

ScanDescriptor MakeDescriptor() {
  ScanDescriptor d;
  d.name = "fragment_3";
  for (int k = 0; k < 2; ++k) {
    ScanDescriptorView v;
    v.color = "images/c" + std::to_string(k) + ".png";
    v.depth = "images/d" + std::to_string(k) + ".png";
    v.intrinsics.fx = 500.25 + k;
    v.intrinsics.fy = 501.5;
    v.intrinsics.cx = 2.0;
    v.intrinsics.cy = 1.5;
    v.depth_scale = k == 0 ? 1000.0 : 5000.0;
    v.T_scan_camera = k == 0 ? Transform::Identity() : SomePose(0.7, 0.1);
    d.views.push_back(v);
  }
  d.views[1].T_world_camera_gt = SomePose(-0.2, 3.0);
  d.cloud = "cloud.ply";
  d.T_world_scan_gt = SomePose(0.45, -2.0);
  return d;
}

TEST(IoDescriptor, WriteReadRoundTrip) {
  TempDir dir;
  const ScanDescriptor d = MakeDescriptor();
  const std::string path = dir.File("scan.json");
  WriteScanDescriptor(path, d);
  const ScanDescriptor back = ReadScanDescriptor(path);
  EXPECT_EQ(back.name, d.name);
  EXPECT_EQ(back.cloud, d.cloud);
  ASSERT_TRUE(back.T_world_scan_gt.has_value());
  EXPECT_EQ(*back.T_world_scan_gt, *d.T_world_scan_gt);  // exact: JSON keeps 17 digits
  ASSERT_EQ(back.views.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back.views[k].color, d.views[k].color);
    EXPECT_EQ(back.views[k].depth, d.views[k].depth);
    EXPECT_EQ(back.views[k].intrinsics.fx, d.views[k].intrinsics.fx);
    EXPECT_EQ(back.views[k].intrinsics.fy, d.views[k].intrinsics.fy);
    EXPECT_EQ(back.views[k].intrinsics.cx, d.views[k].intrinsics.cx);
    EXPECT_EQ(back.views[k].intrinsics.cy, d.views[k].intrinsics.cy);
    EXPECT_EQ(back.views[k].depth_scale, d.views[k].depth_scale);
    EXPECT_EQ(back.views[k].T_scan_camera, d.views[k].T_scan_camera);
    EXPECT_EQ(back.views[k].T_world_camera_gt, d.views[k].T_world_camera_gt);
  }
}

TEST(IoDescriptor, LoadsImagesCloudAndGroundTruth) {
  TempDir dir;
  const ScanDescriptor d = MakeDescriptor();
  WriteColor(dir.File("images/c0.png"), 4, 3);
  WriteColor(dir.File("images/c1.png"), 4, 3);
  WriteDepth(dir.File("images/d0.png"), 4, 3, 2000);
  WriteDepth(dir.File("images/d1.png"), 4, 3, 2000);
  open3d::geometry::PointCloud cloud;
  cloud.points_ = {{0.5, -1.0, 2.0}, {1.0, 2.0, 3.0}, {-0.25, 0.0, 1.5}};
  cloud.colors_ = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ASSERT_TRUE(open3d::io::WritePointCloud(dir.File("cloud.ply"), cloud));
  WriteScanDescriptor(dir.File("scan.json"), d);

  const std::string root = dir.path().string();
  for (const std::string& spec : {root + "/scan.json", root}) {
    const Scan scan = LoadScan(spec);
    EXPECT_EQ(scan.name, "fragment_3");
    ASSERT_EQ(scan.views.size(), 2u);
    ExpectUniformDepth(scan.views[0].depth, 2.0f);  // scale 1000
    ExpectUniformDepth(scan.views[1].depth, 0.4f);  // scale 5000
    EXPECT_EQ(scan.views[0].intrinsics.width, 4);
    EXPECT_EQ(scan.views[1].intrinsics.fx, 501.25);
    EXPECT_EQ(scan.views[1].T_scan_camera, d.views[1].T_scan_camera);
    ASSERT_TRUE(scan.T_world_scan_gt.has_value());
    EXPECT_EQ(*scan.T_world_scan_gt, *d.T_world_scan_gt);
    // View 0 has no explicit ground truth: derived as T_world_scan * T_scan_camera.
    ASSERT_TRUE(scan.views[0].T_world_camera_gt.has_value());
    EXPECT_LT((*scan.views[0].T_world_camera_gt - *d.T_world_scan_gt).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_EQ(*scan.views[1].T_world_camera_gt, *d.views[1].T_world_camera_gt);  // explicit wins
    ASSERT_EQ(scan.points.size(), 3u);
    ASSERT_EQ(scan.colors.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_LT((scan.points[k] - cloud.points_[k]).norm(), 1e-6);
      EXPECT_LT((scan.colors[k] - cloud.colors_[k]).norm(), 1e-6);
    }
  }
}

TEST(IoDescriptor, IntrinsicsFileAndDefaults) {
  TempDir dir;
  WriteColor(dir.File("c.jpg"), 4, 3);
  WriteDepth(dir.File("d.png"), 4, 3, 1000);
  WriteText(dir.File("calib/K.txt"), "300 0 2\n0 310 1.5\n0 0 1\n");
  const Transform gt = SomePose(1.0, 0.25);
  std::string gt_json;
  for (int k = 0; k < 16; ++k) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%s%.17g", k ? ", " : "", gt(k / 4, k % 4));
    gt_json += buffer;
  }
  // No name, depth_scale or T_scan_camera: defaults (file stem, 1000, identity). Ground truth only
  // on the view: T_world_scan_gt = T_world_camera_gt * inv(T_scan_camera).
  WriteText(dir.File("desc.json"), R"({"views": [{"color": "c.jpg", "depth": "d.png",
      "intrinsics_file": "calib/K.txt", "T_world_camera_gt": [)" +
                                       gt_json + "]}]}");
  const Scan scan = LoadScan(dir.File("desc.json"));
  EXPECT_EQ(scan.name, "desc");
  ASSERT_EQ(scan.views.size(), 1u);
  EXPECT_EQ(scan.views[0].intrinsics.fx, 300.0);
  EXPECT_EQ(scan.views[0].intrinsics.fy, 310.0);
  ExpectUniformDepth(scan.views[0].depth, 1.0f);
  EXPECT_TRUE(scan.views[0].T_scan_camera.isIdentity());
  ASSERT_TRUE(scan.T_world_scan_gt.has_value());
  EXPECT_LT((*scan.T_world_scan_gt - gt).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_TRUE(scan.points.empty());
}

TEST(IoScanFromView, OneViewIdentityAndGroundTruth) {
  View view;
  view.name = "v";
  view.T_scan_camera = SomePose();
  view.T_world_camera_gt = SomePose(0.1, 2.0);
  const Scan scan = ScanFromView(view);
  EXPECT_EQ(scan.name, "v");
  ASSERT_EQ(scan.views.size(), 1u);
  EXPECT_TRUE(scan.views[0].T_scan_camera.isIdentity());
  EXPECT_EQ(scan.T_world_scan_gt, view.T_world_camera_gt);
  EXPECT_TRUE(scan.points.empty());
}

}  // namespace
}  // namespace zeroreg
