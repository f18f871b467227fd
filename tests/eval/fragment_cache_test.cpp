// A fused fragment is reused only when everything that made it is the same: the fusion settings,
// the depth scale the frames are read with, and the frames' files themselves.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "fuse/fuse.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

class FragmentCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("zeroreg_fragment_cache_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "data");
    fs::copy_file(testing::RedkitchenDir() + "/camera-intrinsics.txt",
                  dir_ / "data" / "camera-intrinsics.txt");
    for (const char* id : {"000000", "000005"}) {
      for (const char* ext : {".color.jpg", ".depth.png", ".pose.txt"}) {
        const std::string name = std::string("frame-") + id + ext;
        fs::copy_file(testing::RedkitchenDir() + "/frames/" + name, dir_ / "data" / name);
      }
    }
    config_.voxel_length_m = 0.05;
    config_.sdf_trunc_m = 0.2;
    config_.output_voxel_m = 0.05;
  }
  void TearDown() override { fs::remove_all(dir_); }

  bool Fuse(double depth_scale = 0.0) {
    DatasetOptions options;
    options.depth_scale = depth_scale;
    const auto dataset = OpenDataset((dir_ / "data").string(), options);
    return FuseFragment(*dataset, {0, 5}, config_, (dir_ / "fragment").string());
  }

  fs::path dir_;
  FuseConfig config_;
};

TEST_F(FragmentCache, ReusedOnlyWhenTheDepthScaleAndTheFramesAreTheSame) {
  ASSERT_TRUE(Fuse());
  EXPECT_FALSE(Fuse());      // same everything: reused
  EXPECT_FALSE(Fuse(1000));  // the layout's default, given explicitly: the same fragment
  EXPECT_TRUE(Fuse(2000));   // another depth scale: another fragment
  EXPECT_FALSE(Fuse(2000));
  EXPECT_TRUE(Fuse());

  // A frame's file replaced (another depth image under the same name).
  const fs::path depth = dir_ / "data" / "frame-000005.depth.png";
  fs::copy_file(testing::RedkitchenDir() + "/frames/frame-000010.depth.png", depth,
                fs::copy_options::overwrite_existing);
  EXPECT_TRUE(Fuse());
  EXPECT_FALSE(Fuse());
  // Only touched: its time changed, so it may hold other data.
  fs::last_write_time(depth, fs::last_write_time(depth) + std::chrono::seconds(5));
  EXPECT_TRUE(Fuse());
  // The intrinsics and a pose are inputs too.
  std::ofstream(dir_ / "data" / "camera-intrinsics.txt", std::ios::app) << "\n";
  EXPECT_TRUE(Fuse());
  std::ofstream(dir_ / "data" / "frame-000000.pose.txt", std::ios::app) << "\n";
  EXPECT_TRUE(Fuse());
  EXPECT_FALSE(Fuse());
}

}  // namespace
}  // namespace zeroreg
