// Input that is well formed but cannot describe a real scan (a depth scale or intrinsics off by
// orders of magnitude, a folder where a file belongs, too many views), and the messages about
// input (invisible characters, corrupt images, out-of-range ids, misspelt commands, huge values):
// refused where it enters, with exit 2 and a message naming the file or option.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/backends.hpp"
#include "io/io_test_util.hpp"
#include "io/shown.hpp"
#include "pipeline/cli_fixture.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::RunCli;
using testing_io::ExpectInputError;
using testing_io::TempDir;
using testing_io::WriteColor;
using testing_io::WriteDepth;
using testing_io::WriteText;

class BoundaryChecks : public testing::CliBadInput {
 protected:
  // A scan.json for frame 20 of the fixture's folder with `view_extra` added to its view.
  void WriteScanJson(const std::string& intrinsics, const std::string& view_extra = "") const {
    Write("src.json", R"({"views": [{"color": "frame-000020.color.jpg", "depth": )"
                      R"("frame-000020.depth.png", "intrinsics": )" +
                          intrinsics + view_extra + "}]}");
  }
  testing::CommandResult RunScanJson() const {
    return RunCli("register -s '" + Path("src.json") + "' -t '" + Path("") + "@0'");
  }
};

const char* kIntrinsics = R"({"fx": 585, "fy": 585, "cx": 320, "cy": 240})";

// ---- depth scale: its consequence, the depth range, is checked ----------------------------------

TEST_F(BoundaryChecks, DepthScaleOptionGivingImpossibleDepthsIsBadInput) {
  // Millimetres read as metres (1) give ~2 km; 100000 gives ~2 cm: no depth sensor sees either.
  for (const char* scale : {"1", "100000"}) {
    const auto r = Run(std::string("--depth-scale ") + scale);
    ExpectClearError(r, "--depth-scale", "gives depths from");
    EXPECT_NE(r.output.find("frame-000020.depth.png"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("has no normal"), std::string::npos) << r.output;
  }
}

TEST_F(BoundaryChecks, DepthScaleInScanJsonGivingImpossibleDepthsIsBadInput) {
  for (const char* scale : {"1", "1e-300"}) {
    WriteScanJson(kIntrinsics, std::string(R"(, "depth_scale": )") + scale);
    const auto r = RunScanJson();
    ExpectClearError(r, "src.json: views[0].depth_scale", "expected a depth sensor's range");
  }
}

TEST(IoBoundaryChecks, DepthRangeAcceptsSensorDepthsAndNamesTheScale) {
  TempDir dir;
  WriteColor(dir.File("c.png"), 64, 48);
  WriteDepth(dir.File("d.png"), 64, 48, 2000);
  const Intrinsics k{60, 60, 32, 24, 0, 0};
  EXPECT_NEAR(LoadView(dir.File("c.png"), dir.File("d.png"), k, 1000).depth.at<float>(0, 0), 2.0,
              1e-6);
  ExpectInputError([&] { LoadView(dir.File("c.png"), dir.File("d.png"), k, 1); },
                   {"d.png", "depth_scale = 1", "2000 m", "median depth 0.05 to 100 m"});
}

// ---- intrinsics: plausible for the image ----------------------------------------------------

TEST_F(BoundaryChecks, AbsurdIntrinsicsInScanJsonAreBadInput) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"fx": 1e-300, "fy": 585, "cx": 320, "cy": 240})", "focal length fx = 1e-300"},
      {R"({"fx": 585, "fy": 585, "cx": 1e300, "cy": 240})", "principal point cx = 1e+300"},
      {R"({"fx": 585, "fy": 3, "cx": 320, "cy": 240})", "focal length fy = 3 pixels"},
      {R"({"fx": 585, "fy": 585, "cx": 320, "cy": -900})", "principal point cy = -900"},
  };
  for (const auto& [intrinsics, message] : cases) {
    WriteScanJson(intrinsics);
    ExpectClearError(RunScanJson(), "src.json", message);
  }
}

TEST_F(BoundaryChecks, AbsurdIntrinsicsFileIsBadInputNamingIt) {
  Write("camera-intrinsics.txt", "1e-300 0 320\n0 585 240\n0 0 1\n");
  ExpectClearError(Run(), "camera-intrinsics.txt", "focal length fx = 1e-300");
  // Plausible without the image size, implausible for the 640x480 frames.
  Write("camera-intrinsics.txt", "585 0 320\n0 585 2000\n0 0 1\n");
  ExpectClearError(Run(), "camera-intrinsics.txt", "principal point cy = 2000");
}

// ---- files where a file belongs -------------------------------------------------------------

TEST_F(BoundaryChecks, PoseFileThatIsAFolderIsBadInput) {
  fs::remove(Path("frame-000020.pose.txt"));
  fs::create_directory(Path("frame-000020.pose.txt"));
  ExpectClearError(Run(), "frame-000020.pose.txt", "pose file is not a regular file (a folder)");
}

// ---- views per scan -------------------------------------------------------------------------

TEST_F(BoundaryChecks, ViewsPerScanAreBounded) {
  nlohmann::json views = nlohmann::json::array();
  for (int k = 0; k < 65; ++k) {
    views.push_back({{"color", "frame-000020.color.jpg"},
                     {"depth", "frame-000020.depth.png"},
                     {"intrinsics", {{"fx", 585}, {"fy", 585}, {"cx", 320}, {"cy", 240}}}});
  }
  Write("src.json", nlohmann::json{{"views", views}}.dump());
  const auto r = RunScanJson();
  ExpectClearError(r, "src.json", "lists 65 views, more than the limit of 64");
  EXPECT_NE(r.output.find("ZEROREG_MAX_VIEWS"), std::string::npos) << r.output;
}

// ---- messages -------------------------------------------------------------------------------

// A complete JPEG (it ends with the end-of-image marker) whose segments are broken.
TEST_F(BoundaryChecks, CorruptJpegIsNotCalledTruncated) {
  std::ifstream in(Path("frame-000020.color.jpg"), std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  ASSERT_GT(bytes.size(), 100u);
  // The first segment (APP0) starts at byte 2; the byte after it must be a marker's 0xFF.
  const size_t length =
      (static_cast<unsigned char>(bytes[4]) << 8) | static_cast<unsigned char>(bytes[5]);
  bytes[2 + 2 + length] = 0x12;
  std::ofstream(Path("frame-000020.color.jpg"), std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  const auto r = Run();
  ExpectClearError(r, "frame-000020.color.jpg", "is a corrupt JPEG file");
  EXPECT_EQ(r.output.find("truncated"), std::string::npos) << r.output;
}

TEST(IoBoundaryChecks, ByteOrderMarkStartingATextFileIsAccepted) {
  TempDir dir;
  WriteText(dir.File("k.txt"),
            "\xEF\xBB\xBF"
            "585 0 320\n0 585 240\n0 0 1\n");
  const Intrinsics k = ReadIntrinsicsFile(dir.File("k.txt"), 0, 0);
  EXPECT_EQ(k.fx, 585);
  EXPECT_EQ(k.cy, 240);
  WriteText(dir.File("pose.txt"),
            "\xEF\xBB\xBF"
            "1 0 0 0.5\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(ReadPoseFile(dir.File("pose.txt"))(0, 3), 0.5);
}

TEST(IoBoundaryChecks, InvisibleCharactersInATokenAreNamed) {
  TempDir dir;
  // A no-break space glued to a number, and a byte order mark that does not start the file.
  WriteText(dir.File("k.txt"), "585\xC2\xA0 0 320\n0 585 240\n0 0 1\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("k.txt"), 0, 0); },
                   {"k.txt", "line 1", "'585<U+00A0>'", "U+00A0 (no-break space)"});
  WriteText(dir.File("k.txt"),
            "585 0 320\n\xEF\xBB\xBF"
            "0 585 240\n0 0 1\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("k.txt"), 0, 0); },
                   {"line 2", "U+FEFF (byte order mark)"});
}

TEST_F(BoundaryChecks, OutOfRangeFrameIdSaysSo) {
  const auto r = RunCli("register -s '" + Path("") + "@99999999999' -t '" + Path("") + "@0'");
  ExpectClearError(r, "@99999999999", "frame id 99999999999 is out of range");
  EXPECT_NE(r.output.find("[0, 999999999]"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("not a non-negative integer"), std::string::npos) << r.output;
  ExpectClearError(RunCli("register -s '" + Path("") + "@-1' -t '" + Path("") + "@0'"), "@-1",
                   "not a non-negative integer");
}

TEST(CliBoundaryChecks, MisspeltCommandIsNamedWithTheNearest) {
  auto r = RunCli("regster -s a -t b");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown command 'regster' (did you mean 'register'?)"),
            std::string::npos)
      << r.output;
  r = RunCli("eval 3dmach");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("zeroreg eval: unknown command '3dmach' (did you mean '3dmatch'?)"),
            std::string::npos)
      << r.output;
  r = RunCli("frobnicate");  // nothing near: no guess, the list
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown command 'frobnicate'; expected one of: register,"),
            std::string::npos)
      << r.output;
}

// Every iteration count of the config is bounded, so that no accepted setting runs for ever.
TEST_F(BoundaryChecks, IterationCountsAreBounded) {
  const std::pair<const char*, const char*> cases[] = {
      {"match.sinkhorn.iterations=2147483647", "expected an integer in [1, 1000]"},
      {"ransac.max_iterations=10000001", "expected an integer in [1, 10000000]"},
      {"ransac.clique_max_search_nodes=1000001", "expected an integer in [1, 1000000]"},
      {"ransac.clique_max_correspondences=20001", "expected an integer in [3, 20000]"},
      {"refine.coarse_iterations=1001", "expected an integer in [0, 1000]"},
      {"refine.max_iterations=1001", "expected an integer in [0, 1000]"},
      {"segmenter.grabcut_iterations=51", "expected an integer in [1, 50]"},
      {"object_match.restarts=101", "expected an integer in [1, 100]"},
      {"object_match.iterations=1001", "expected an integer in [1, 1000]"},
      {"features.max_keypoints=16385", "expected an integer in [1, 16384]"},
  };
  for (const auto& [assignment, message] : cases) {
    ExpectClearError(
        RunCli("register -s '" + Path("") + "@20' -t '" + Path("") + "@0' --set " + assignment, 60),
        std::string("--set ") + assignment, message);
  }
}

TEST(IoBoundaryChecks, EchoedValuesAreBounded) {
  const std::string label(1 << 20, 'x');
  const std::string shown = detail::ShownText(label);
  EXPECT_LT(shown.size(), 200u);
  EXPECT_NE(shown.find("1048576 bytes"), std::string::npos) << shown;
  EXPECT_EQ(detail::ShownNumber(1e300), "1e+300");
  EXPECT_EQ(detail::ShownText("a\x01z"), "a<U+0001>z");
  EXPECT_EQ(detail::ShownText("caf\xC3\xA9"), "caf\xC3\xA9");  // visible UTF-8 stays
  EXPECT_EQ(detail::ShownText("\xFF"), "<0xFF>");

  // A box of 1e300 in a detections file: its message stays short.
  TempDir dir;
  WriteText(dir.File("dets/img.json"),
            R"({"detections": [{"box": [0, 0, 1e300, 10], "label": "chair"}]})");
  DetectorConfig config;
  config.detections_dir = dir.File("dets");
  FileDetector detector(config);
  const cv::Mat image(48, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  try {
    detector.Detect(image, "img.png");
    ADD_FAILURE() << "a box outside the image was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("1e+300"), std::string::npos) << message;
    EXPECT_LT(message.size(), 300u) << message;
  }
}

}  // namespace
}  // namespace zeroreg
