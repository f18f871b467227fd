// `zeroreg info` without a scan: what a bug report needs (version, inference engine and why,
// Open3D module, assets and whether they verify), each line checked against the build.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_paths.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::RunCli;

// The text after `prefix` up to the end of its line, or "" when no line starts with it.
std::string LineAfter(const std::string& output, const std::string& prefix) {
  std::size_t at = output.rfind("\n" + prefix);
  if (output.compare(0, prefix.size(), prefix) == 0) at = 0;
  if (at == std::string::npos) return "";
  if (at != 0) ++at;
  const std::size_t begin = at + prefix.size();
  return output.substr(begin, output.find('\n', begin) - begin);
}

TEST(CliInfo, FirstLineIsTheVersion) {
  const auto r = RunCli("info");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.substr(0, r.output.find('\n')), std::string("zeroreg ") + ZEROREG_VERSION);
}

TEST(CliInfo, SaysWhichEngineRunsAndWhy) {
  const auto r = RunCli("info");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string engine = LineAfter(r.output, "inference engine: ");
  const std::string ort = LineAfter(r.output, "  onnxruntime: ");
#ifdef ZEROREG_TEST_WITH_ONNXRUNTIME
  EXPECT_EQ(engine, "onnxruntime (inference.engine = auto, and this build links ONNX Runtime)");
  // "ONNX Runtime 1.29.0, /path/libonnxruntime.so.1.29.0": the file the loader opened exists.
  ASSERT_EQ(ort.rfind("ONNX Runtime 1.", 0), 0u) << ort;
  const std::string library = ort.substr(ort.find(", ") + 2);
  EXPECT_NE(library.find("libonnxruntime.so"), std::string::npos) << library;
  EXPECT_TRUE(fs::is_regular_file(library)) << library;
#else
  EXPECT_EQ(engine, "opencv (inference.engine = auto, and this build has no ONNX Runtime)");
  EXPECT_EQ(ort.rfind("not in this build", 0), 0u) << ort;
#endif
  EXPECT_EQ(LineAfter(r.output, "  opencv: ").rfind("OpenCV 4.", 0), 0u) << r.output;
}

TEST(CliInfo, EngineAskedForByConfigIsNamedAsTheReason) {
  const auto r = RunCli("info --set inference.engine=opencv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(LineAfter(r.output, "inference engine: "), "opencv (inference.engine = opencv)");
}

// A config naming an engine this build does not have is bad input (exit 2), but the rest of the
// report still prints: it is what the user needs to see.
TEST(CliInfo, UnknownEngineIsBadInputAndTheReportStillPrints) {
  const auto r = RunCli("info --set inference.engine=tpu");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(LineAfter(r.output, "inference engine: ")
                .rfind("NONE: inference.engine: unknown engine 'tpu'", 0),
            0u)
      << r.output;
  EXPECT_NE(r.output.find("\nassets: "), std::string::npos) << r.output;
}

TEST(CliInfo, AssetsOfTheRepositoryVerifyAndTheOpen3dModuleLoads) {
  const auto r = RunCli("info");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  if (std::getenv("ZEROREG_ASSETS") == nullptr) {
    const std::string assets = LineAfter(r.output, "assets: ");
    EXPECT_TRUE(fs::exists(assets) && fs::equivalent(assets, testing::RepoDir() + "/assets"))
        << r.output;
  }
  EXPECT_NE(r.output.find(" model files, sha256 ok\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("NOT OK"), std::string::npos) << r.output;
  EXPECT_NE(LineAfter(r.output, "open3d module: ").find("libzeroreg-open3d.so (loads;"),
            std::string::npos)
      << r.output;
}

// A damaged copy of the assets: info names the file that does not verify and counts the others,
// instead of stopping at the first problem.
TEST(CliInfo, DamagedAssetsAreNamedOneByOne) {
  const fs::path dir = fs::temp_directory_path() / ("zeroreg_info_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "xfeat");
  fs::copy_file(testing::RepoDir() + "/scripts/assets.sha256", dir / "assets.sha256");
  std::ofstream(dir / "xfeat" / "xfeat_any_size.onnx", std::ios::binary) << "not a model";
  const auto r = RunCli("info --assets '" + dir.string() + "'");
  fs::remove_all(dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("NOT OK"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("xfeat/xfeat_any_size.onnx"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" model files do not verify (bash scripts/fetch-assets.sh)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("sha256 ok"), std::string::npos) << r.output;
}

// With a scan, info says at which scale it will be registered (docs/CONFIG.md, "Any scale"): the
// kitchen frame as it is (a room: the config's lengths as written) and read with ten times the
// depth units (the same frame as a scene seen from 12-25 cm, by a sensor ten times finer).
TEST(CliInfo, ScanSaysItsWorkingDistanceAndScale) {
  const std::string frame = testing::RedkitchenDir() + "/frames/frame-000000";
  const auto room = RunCli("info --scan '" + testing::RedkitchenDir() + "@0'");
  ASSERT_EQ(room.exit_code, 0) << room.output;
  EXPECT_NE(room.output.find("working distance 1.88 m"), std::string::npos) << room.output;
  EXPECT_NE(room.output.find("working scale 1 (read from the structured-light noise): the "
                             "config's lengths apply as written"),
            std::string::npos)
      << room.output;
  const fs::path dir = testing::FreshTestDir("zeroreg_info_scale_");
  const fs::path descriptor = dir / "near.json";
  std::ofstream(descriptor) << R"({"views": [{"color": ")" << frame << R"(.color.jpg", "depth": ")"
                            << frame << R"(.depth.png", "depth_scale": 10000,
      "intrinsics": {"fx": 585, "fy": 585, "cx": 320, "cy": 240}}]})";
  const auto near = RunCli("info --scan '" + descriptor.string() + "'");
  ASSERT_EQ(near.exit_code, 0) << near.output;
  EXPECT_NE(near.output.find("working distance 0.188 m"), std::string::npos) << near.output;
  // The Kinect's noise in inverse depth, ten times the frame's: k = 0.1 (its nearest quarter
  // octave, 2^(-13/4)); the distance alone would give 0.177.
  EXPECT_NE(near.output.find("working scale 0.105 (read from the structured-light noise)"),
            std::string::npos)
      << near.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace zeroreg
