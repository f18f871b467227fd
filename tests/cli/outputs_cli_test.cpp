// The command line never writes over what it reads or over results it does not own: `register`
// refuses an output that is one of its inputs, re-running into an --out-dir leaves none of the
// previous run's pictures, `fuse -o` a file is a clear error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pipeline/cli_fixture.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg::testing {
namespace {

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

using RegisterOutputs = CliBadInput;

// The error names the output option, the path and the input option it would overwrite; the input
// is left as it was.
void ExpectRefused(const CommandResult& r, const std::string& path, const std::string& input,
                   const std::string& bytes_before) {
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(input), std::string::npos) << r.output;
  EXPECT_EQ(ReadBytes(path), bytes_before) << path << " was overwritten";
}

TEST_F(RegisterOutputs, OutNamingAnInputIsRefused) {
  const std::string image = Path("frame-000020.color.jpg");
  const std::string depth = Path("frame-000000.depth.png");
  for (const auto& [path, input] : {std::pair{image, "--source"}, std::pair{depth, "--target"}}) {
    const std::string before = ReadBytes(path);
    ExpectRefused(Run("--features sift --out '" + path + "'"), path, input, before);
  }
  // The --gt file, also through a link to it.
  const std::string gt = Path("gt.txt");
  Write("gt.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  const std::string gt_text = ReadBytes(gt);
  ExpectRefused(Run("--features sift --gt '" + gt + "' --out '" + gt + "'"), gt, "--gt", gt_text);
  std::filesystem::create_symlink(gt, Path("alias.txt"));
  const auto alias = Run("--features sift --gt '" + gt + "' --out '" + Path("alias.txt") + "'");
  EXPECT_EQ(alias.exit_code, 2) << alias.output;
  EXPECT_EQ(ReadBytes(gt), gt_text);
  // --out-dir whose result.json is the --gt file.
  std::filesystem::create_directories(Path("run"));
  Write("run/result.json", gt_text);
  const auto dir =
      Run("--features sift --gt '" + Path("run/result.json") + "' --out-dir '" + Path("run") + "'");
  EXPECT_EQ(dir.exit_code, 2) << dir.output;
  EXPECT_NE(dir.output.find("--gt"), std::string::npos) << dir.output;
  EXPECT_EQ(ReadBytes(Path("run/result.json")), gt_text);
}

TEST_F(RegisterOutputs, OutNamingAScanDescriptorOrItsFilesIsRefused) {
  ScanDescriptor descriptor;
  ScanDescriptorView view;
  view.color = "frame-000020.color.jpg";
  view.depth = "frame-000020.depth.png";
  view.intrinsics = ReadIntrinsicsFile(Path("camera-intrinsics.txt"), 0, 0);
  descriptor.views.push_back(view);
  WriteScanDescriptor(Path("scan.json"), descriptor);
  for (const std::string& out : {Path("scan.json"), Path("frame-000020.depth.png")}) {
    const std::string before = ReadBytes(out);
    const auto r = RunCli("register --source '" + Path("scan.json") + "' --target '" +
                          dir_.string() + "@0' --features sift --out '" + out + "'");
    ExpectRefused(r, out, "--source", before);
  }
}

// A second run into the same --out-dir: the pictures of the first that the second does not
// write (more views, the candidates' picture) are gone; files the run does not own stay.
TEST_F(RegisterOutputs, RerunIntoOutDirLeavesNoPictureOfThePreviousRun) {
  const std::filesystem::path pictures = dir_ / "run" / "pictures";
  std::filesystem::create_directories(pictures);
  const std::string stale_picture = ReadBytes(Path("frame-000000.color.jpg"));
  for (const char* name : {"objects-view5.png", "registered-view5.png",
                           "correspondences-view0-3.png", "hypotheses-view4.png"}) {
    std::ofstream(pictures / name, std::ios::binary) << stale_picture;
  }
  Write("run/notes.txt", "mine\n");
  const auto r = Run("--features sift --out-dir '" + Path("run") + "'");
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
  EXPECT_TRUE(std::filesystem::exists(pictures / "registered-view0.png"));
  for (const char* name : {"objects-view5.png", "registered-view5.png",
                           "correspondences-view0-3.png", "hypotheses-view4.png"}) {
    EXPECT_FALSE(std::filesystem::exists(pictures / name)) << name << " of the previous run";
  }
  EXPECT_EQ(ReadBytes(Path("run/notes.txt")), "mine\n");
}

TEST_F(RegisterOutputs, FuseIntoAnExistingFileIsAClearError) {
  Write("fragment", "a file\n");
  const auto r = RunCli("fuse --dataset '" + dir_.string() + "' --frames 0,20 --voxel 0.05 -o '" +
                        Path("fragment") + "'");
  ExpectClearError(r, Path("fragment"), "expected a folder");
  EXPECT_EQ(ReadBytes(Path("fragment")), "a file\n");
}

// More views than a scan.json may hold would make a fragment no command can read back.
TEST_F(RegisterOutputs, FuseRefusesMoreViewsThanAScanHolds) {
  const auto r = RunCli("fuse --dataset '" + dir_.string() + "' --frames 0,20 --views 65 -o '" +
                        Path("fragment") + "'");
  ExpectClearError(r, "--views", "expected at most 64");
  EXPECT_FALSE(std::filesystem::exists(Path("fragment")));
}

}  // namespace
}  // namespace zeroreg::testing
