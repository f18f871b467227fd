// Frame and pose conventions checked against the real 7-Scenes redkitchen frames and the official
// 3DMatch benchmark files (../shared/data, see the MANIFEST.md files there).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/io_test_util.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing_io::TempDir;

const std::string kKitchen = ZEROREG_REPO_DIR "/../shared/data/7scenes-redkitchen";
const std::string kFrames = kKitchen + "/frames";
const std::string kGtLog =
    ZEROREG_REPO_DIR "/../shared/data/3dmatch-gt/3DMatch/7-scenes-redkitchen/gt.log";
const std::string kGtInfo =
    ZEROREG_REPO_DIR "/../shared/data/3dmatch-gt/3DMatch/7-scenes-redkitchen/gt.info";
const std::string kLoGtLog =
    ZEROREG_REPO_DIR "/../shared/data/3dmatch-gt/3DLoMatch/7-scenes-redkitchen/gt.log";

std::string PosePath(int frame) {
  char name[64];
  std::snprintf(name, sizeof(name), "/frame-%06d.pose.txt", frame);
  return kFrames + name;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// gt.log "i j" is T_i_j = inv(P[50 i]) * P[50 j]: fragment k starts at frame 50k and is expressed
// in that frame's camera (MANIFEST of 7scenes-redkitchen). This pins down both the pose-file
// convention (camera-to-world) and the gt.log direction (maps j into i).
TEST(IoRealData, GtLogEqualsRelativeFramePoses) {
  for (const std::string& log : {kGtLog, kLoGtLog}) {
    const std::vector<LogEntry> entries = ReadLogFile(log);
    int checked = 0;
    for (const LogEntry& e : entries) {
      if (e.i >= 20 || e.j >= 20) continue;
      const Transform expected =
          ReadPoseFile(PosePath(50 * e.i)).inverse() * ReadPoseFile(PosePath(50 * e.j));
      EXPECT_LT((expected - e.T_i_j).cwiseAbs().maxCoeff(), 1e-6)
          << log << " pair " << e.i << " " << e.j;
      ++checked;
    }
    // 122 3DMatch and 42 3DLoMatch pairs have both fragments in frames 0..999.
    EXPECT_EQ(checked, log == kGtLog ? 122 : 42);
  }
}

// Median |depth residual| of frame b's depth moved into frame a with T_a_b, against frame a's
// depth.
double MedianReprojectionResidual(const View& a, const View& b, const Transform& T_a_b,
                                  int* count) {
  std::vector<double> residuals;
  const Intrinsics& kb = b.intrinsics;
  const Intrinsics& ka = a.intrinsics;
  for (int v = 0; v < b.depth.rows; v += 2) {
    for (int u = 0; u < b.depth.cols; u += 2) {
      const float z = b.depth.at<float>(v, u);
      if (z <= 0) continue;
      const Eigen::Vector4d xb((u - kb.cx) * z / kb.fx, (v - kb.cy) * z / kb.fy, z, 1.0);
      const Eigen::Vector4d xa = T_a_b * xb;
      if (xa.z() <= 0.1) continue;
      const int ua = static_cast<int>(std::lround(ka.fx * xa.x() / xa.z() + ka.cx));
      const int va = static_cast<int>(std::lround(ka.fy * xa.y() / xa.z() + ka.cy));
      if (ua < 0 || va < 0 || ua >= a.depth.cols || va >= a.depth.rows) continue;
      const float za = a.depth.at<float>(va, ua);
      if (za <= 0) continue;
      residuals.push_back(std::abs(za - xa.z()));
    }
  }
  *count = static_cast<int>(residuals.size());
  if (residuals.empty()) return 1e9;
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  return residuals[residuals.size() / 2];
}

TEST(IoRealData, PoseCompositionReprojectsDepth) {
  const auto dataset = OpenDataset(kKitchen);
  const View f0 = dataset->LoadFrame(0);
  const View f20 = dataset->LoadFrame(20);
  ASSERT_TRUE(f0.T_world_camera_gt && f20.T_world_camera_gt);
  const Transform T_0_20 = f0.T_world_camera_gt->inverse() * *f20.T_world_camera_gt;
  int count = 0;
  const double median = MedianReprojectionResidual(f0, f20, T_0_20, &count);
  EXPECT_GT(count, 20000);
  EXPECT_LT(median, 0.03);  // MANIFEST measured 0.6 cm
  // The opposite convention (world-to-camera files) must be clearly worse, else the check is blind.
  const Transform wrong = *f0.T_world_camera_gt * f20.T_world_camera_gt->inverse();
  const double wrong_median = MedianReprojectionResidual(f0, f20, wrong, &count);
  EXPECT_GT(wrong_median, 2.0 * median);
  std::printf("frame 20 -> 0 median depth residual %.4f m (wrong convention %.4f m)\n", median,
              wrong_median);
}

TEST(IoRealData, OpensFolderAndFramesFolder) {
  for (const std::string& root : {kKitchen, kFrames, kFrames + "/"}) {
    const auto dataset = OpenDataset(root);
    EXPECT_EQ(dataset->layout(), DatasetLayout::kThreeDMatch);
    EXPECT_EQ(dataset->root(), root);
    const std::vector<int> ids = dataset->FrameIds();
    ASSERT_EQ(ids.size(), 1000u);
    EXPECT_EQ(ids.front(), 0);
    EXPECT_EQ(ids.back(), 999);
    const View view = dataset->LoadFrame(300);
    EXPECT_EQ(view.name, "7scenes-redkitchen@300");
    EXPECT_EQ(view.color.type(), CV_8UC3);
    EXPECT_EQ(view.depth.type(), CV_32FC1);
    EXPECT_EQ(view.color.size(), cv::Size(640, 480));
    EXPECT_EQ(view.intrinsics.fx, 585.0);
    EXPECT_EQ(view.intrinsics.fy, 585.0);
    EXPECT_EQ(view.intrinsics.cx, 320.0);
    EXPECT_EQ(view.intrinsics.cy, 240.0);
    EXPECT_EQ(view.intrinsics.width, 640);
    EXPECT_EQ(view.intrinsics.height, 480);
    ASSERT_TRUE(view.T_world_camera_gt.has_value());
    EXPECT_EQ(*view.T_world_camera_gt, ReadPoseFile(PosePath(300)));
  }
}

TEST(IoRealData, DepthIsMetresWithInvalidZeroed) {
  const auto dataset = OpenDataset(kKitchen);
  const View view = dataset->LoadFrame(0);
  double max_depth = 0;
  cv::minMaxLoc(view.depth, nullptr, &max_depth);
  // 65535 (invalid) must not survive as 65.535 m; 7-Scenes depth is below 10 m.
  EXPECT_LT(max_depth, 10.0);
  std::vector<float> valid;
  for (int r = 0; r < view.depth.rows; ++r) {
    for (int c = 0; c < view.depth.cols; ++c) {
      if (view.depth.at<float>(r, c) > 0) valid.push_back(view.depth.at<float>(r, c));
    }
  }
  ASSERT_FALSE(valid.empty());
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  // MANIFEST: median valid depth per frame 1.19-2.45 m.
  EXPECT_GT(valid[valid.size() / 2], 1.0);
  EXPECT_LT(valid[valid.size() / 2], 2.6);
}

TEST(IoRealData, LoadScanSpecsAgree) {
  const Scan by_id = LoadScan(kKitchen + "@20");
  const Scan by_image = LoadScan(kFrames + "/frame-000020.color.jpg");
  for (const Scan* scan : {&by_id, &by_image}) {
    ASSERT_EQ(scan->views.size(), 1u);
    EXPECT_TRUE(scan->points.empty());
    EXPECT_TRUE(scan->views[0].T_scan_camera.isIdentity());
    ASSERT_TRUE(scan->T_world_scan_gt.has_value());
    EXPECT_EQ(*scan->T_world_scan_gt, ReadPoseFile(PosePath(20)));
  }
  EXPECT_EQ(cv::norm(by_id.views[0].depth, by_image.views[0].depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(by_id.views[0].color, by_image.views[0].color, cv::NORM_INF), 0.0);
  EXPECT_EQ(by_image.views[0].intrinsics.fx, 585.0);  // intrinsics found in the parent folder
}

TEST(IoLogs, RealGtLogRoundTripsByteForByte) {
  const std::vector<LogEntry> entries = ReadLogFile(kGtLog);
  ASSERT_EQ(entries.size(), 506u);  // MANIFEST of 3dmatch-gt
  EXPECT_EQ(entries[0].i, 0);
  EXPECT_EQ(entries[0].j, 1);
  EXPECT_EQ(entries[0].n, 60);
  EXPECT_DOUBLE_EQ(entries[0].T_i_j(0, 0), 9.96926560e-01);
  EXPECT_DOUBLE_EQ(entries[0].T_i_j(1, 3), -3.87705398e-02);
  TempDir dir;
  const std::string out = dir.File("est.log");
  WriteLogFile(out, entries);
  EXPECT_EQ(ReadBytes(out), ReadBytes(kGtLog));
}

TEST(IoLogs, RealGtInfo) {
  const std::vector<InfoEntry> entries = ReadInfoFile(kGtInfo);
  ASSERT_EQ(entries.size(), 506u);
  EXPECT_EQ(entries[0].i, 0);
  EXPECT_EQ(entries[0].j, 1);
  EXPECT_DOUBLE_EQ(entries[0].information(0, 0), 5000.0);
  EXPECT_DOUBLE_EQ(entries[0].information(0, 4), 1.08436729e+04);
  for (const InfoEntry& e : entries) {
    EXPECT_LT((e.information - e.information.transpose()).cwiseAbs().maxCoeff(), 1e-3);
  }
}

TEST(IoLogs, WriteReadRoundTrip) {
  std::vector<LogEntry> entries;
  for (int k = 0; k < 5; ++k) {
    LogEntry e;
    e.i = k;
    e.j = k + 3;
    e.n = 57;
    e.T_i_j = testing_io::SomePose(0.2 * k - 0.4, -1.5 + k);
    e.T_i_j(0, 3) = k * 1e-9;  // tiny values survive in %e format
    entries.push_back(e);
  }
  TempDir dir;
  const std::string path = dir.File("est.log");
  WriteLogFile(path, entries);
  const std::vector<LogEntry> back = ReadLogFile(path);
  ASSERT_EQ(back.size(), entries.size());
  for (size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].i, entries[k].i);
    EXPECT_EQ(back[k].j, entries[k].j);
    EXPECT_EQ(back[k].n, entries[k].n);
    // %.8e keeps 9 significant digits: relative error <= 5e-9.
    EXPECT_LT((back[k].T_i_j - entries[k].T_i_j).cwiseAbs().maxCoeff(), 1e-8);
  }
  // No entries: an empty file, read back as no entries.
  WriteLogFile(dir.File("empty.log"), {});
  EXPECT_TRUE(ReadLogFile(dir.File("empty.log")).empty());
}

}  // namespace
}  // namespace zeroreg
