// The command line on good and bad input: every bad input exits with code 2 and a message that
// names the file and the problem; nothing crashes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "features/xfeat_extractor.hpp"
#include "pipeline/cli_fixture.hpp"
#include "test_paths.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::CliBadInput;
using testing::RedkitchenDir;
using testing::RunCli;
using testing::SharedDir;

TEST_F(CliBadInput, ControlCaseRegisters) {
  const auto r = Run("--out '" + Path("result.json") + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(Path("result.json"));
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["result"]["valid"].get<bool>());
  EXPECT_LT(j["ground_truth"]["rotation_error_deg"].get<double>(), 5.0);
  EXPECT_LT(j["ground_truth"]["translation_error_cm"].get<double>(), 10.0);
  EXPECT_TRUE(j["config"].contains("ransac"));
  EXPECT_TRUE(j["result"]["timings_ms"].contains("total"));
  EXPECT_EQ(j["result"]["zeroreg_version"], ZEROREG_VERSION);
}

TEST(Cli, VersionIsTheProjectVersion) {
  const auto r = RunCli("--version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "zeroreg " ZEROREG_VERSION "\n");
}

// `info --scan` says how noisy each view's depth is (what the noise floors use): Kinect v1
// measures ~1.7 mm at 1 m, below the "noisy" line.
TEST(Cli, InfoPrintsTheDepthNoise) {
  const auto r = RunCli("info --scan '" + RedkitchenDir() + "@0'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("depth noise 1."), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("depth noise of the scan (median of its views): 1."), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("noisier than"), std::string::npos) << r.output;
}

// It also says how much of the missing depth lies in thin gaps (not object outlines): a few
// percent on a Kinect v1 frame, a quarter or more on a HoloLens frame (rings of 1-2 px gaps).
TEST(Cli, InfoPrintsTheThinGapShare) {
  const auto share = [](const std::string& scan) {
    const auto r = RunCli("info --scan '" + scan + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::string tail = "% of the missing depth in gaps thinner than 3 px";
    const size_t end = r.output.find(tail);
    if (end == std::string::npos) {
      ADD_FAILURE() << r.output;
      return -1.0;
    }
    const size_t start = r.output.rfind(", ", end) + 2;
    return std::stod(r.output.substr(start, end - start));
  };
  const double kinect = share(RedkitchenDir() + "@0");
  const double hololens = share(SharedDir() + "/data/hololens-office@41");
  EXPECT_GE(kinect, 0.0);
  EXPECT_LT(kinect, 5.0);
  EXPECT_GT(hololens, 20.0);
}

TEST_F(CliBadInput, MissingFile) {
  fs::remove(Path("frame-000020.depth.png"));
  ExpectClearError(Run(), "frame-000020.depth.png", "not found");
}

TEST_F(CliBadInput, MissingScanSpec) {
  const auto r = RunCli("register --source '" + Path("nope") + "@3' --target '" + Path("") + "@0'");
  ExpectClearError(r, "nope", "not found");
}

TEST_F(CliBadInput, ColorDepthSizeMismatch) {
  cv::Mat small = cv::imread(Path("frame-000020.color.jpg"));
  cv::resize(small, small, cv::Size(320, 240));
  cv::imwrite(Path("frame-000020.color.jpg"), small);
  ExpectClearError(Run(), "frame-000020", "320x240");
}

TEST_F(CliBadInput, UnreadableImage) {
  Write("frame-000020.color.jpg", "this is not a JPEG");
  ExpectClearError(Run(), "frame-000020.color.jpg", "cannot");
}

TEST_F(CliBadInput, AllInvalidDepth) {
  cv::imwrite(Path("frame-000020.depth.png"), cv::Mat(480, 640, CV_16U, cv::Scalar(0)));
  ExpectClearError(Run(), "frame-000020.depth.png", "valid");
}

TEST_F(CliBadInput, MissingIntrinsics) {
  fs::remove(Path("camera-intrinsics.txt"));
  ExpectClearError(Run(), "camera-intrinsics.txt", "not found");
}

TEST_F(CliBadInput, MalformedIntrinsics) {
  Write("camera-intrinsics.txt", "585 0 320\n0 585\n");
  ExpectClearError(Run(), "camera-intrinsics.txt", "5 numbers");
}

TEST_F(CliBadInput, MalformedPose) {
  Write("frame-000020.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 zero\n0 0 0 1\n");
  ExpectClearError(Run(), "frame-000020.pose.txt", "zero");
}

// The XFeat file the default config needs: xfeat_any_size.onnx (made by fetch-assets) with ONNX
// Runtime, the 640x640 export with OpenCV DNN.
std::string DefaultXFeatFile() { return XFeatExtractor::ModelFile({}); }

TEST_F(CliBadInput, MissingModelFile) {
  fs::create_directories(dir_ / "assets");
  const auto r = Run("--assets '" + Path("assets") + "'");
  ExpectClearError(r, fs::path(DefaultXFeatFile()).filename().string(), "missing");
  ExpectClearError(r, "run bash scripts/fetch-assets.sh", "missing");
}

TEST_F(CliBadInput, CorruptModelFileFailsItsChecksum) {
  const fs::path file = dir_ / "assets" / DefaultXFeatFile();
  fs::create_directories(file.parent_path());
  fs::copy_file(testing::RepoDir() + "/assets/" + DefaultXFeatFile(), file);
  fs::resize_file(file, 1000);  // truncated download
  const auto r = Run("--assets '" + Path("assets") + "'");
  ExpectClearError(r, file.filename().string(), "sha256");
}

TEST_F(CliBadInput, UnknownConfigKey) {
  Write("config.json", R"({"ransac": {"inlier_treshold_m": 0.05}})");
  ExpectClearError(Run("--config '" + Path("config.json") + "'"), "config.json",
                   "unknown key 'ransac.inlier_treshold_m'");
}

TEST(Cli, SameCommandTwiceGivesIdenticalResult) {
  const std::string args = "register --source '" + RedkitchenDir() + "@20' --target '" +
                           RedkitchenDir() + "@0' --with-correspondences --out ";
  const std::string a = (fs::temp_directory_path() / "zeroreg_det_a.json").string();
  const std::string b = (fs::temp_directory_path() / "zeroreg_det_b.json").string();
  const auto ra = RunCli(args + a), rb = RunCli(args + b);
  ASSERT_EQ(ra.exit_code, 0) << ra.output;
  ASSERT_EQ(rb.exit_code, 0) << rb.output;
  EXPECT_EQ(testing::TakeResultWithoutTimings(a), testing::TakeResultWithoutTimings(b));
}

// An ambiguous result is not valid: exit 1, `ambiguous` and both poses in the JSON, and
// --out-dir draws both overlays (tum-fr3-cabinet 31 -> 9, seen from opposite sides).
TEST(Cli, AmbiguousResultExitsOneWithBothPoses) {
  const std::string cabinet = SharedDir() + "/data/tum-fr3-cabinet@";
  const fs::path dir = testing::FreshTestDir("zeroreg_cli_ambiguous");
  const auto r = RunCli("register --source '" + cabinet + "31' --target '" + cabinet +
                        "9' --set ambiguity.decisive_inliers=50 --out-dir '" + dir.string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  std::ifstream in(dir / "result.json");
  const nlohmann::json j = nlohmann::json::parse(in)["result"];
  EXPECT_FALSE(j["valid"].get<bool>());
  EXPECT_TRUE(j["ambiguous"].get<bool>());
  EXPECT_EQ(j["refusal"]["test"], "ambiguous");
  EXPECT_GE(j["alternatives"].size(), 2u);
  EXPECT_EQ(j["alternatives"][0]["T_target_source"], j["T_target_source"]);
  EXPECT_TRUE(fs::exists(dir / "pictures" / "ambiguous-view0.png"));
  fs::remove_all(dir);
}

TEST(Cli, ErrorsAreReportedInTheSameOrderForAnyThreadCount) {
  // With threads >= 2 the scans are read at once while the models load; the error reported is
  // still the first in the serial order: the source's, the target's, --gt's, then the models'.
  const std::string good = "'" + RedkitchenDir() + "@0'";
  const std::string no_assets =
      " --set assets_dir='" + (fs::temp_directory_path() / "zeroreg_no_assets").string() + "'";
  for (const char* threads : {"1", "2"}) {
    const std::string t = std::string(" --set threads=") + threads + no_assets;
    const auto both = RunCli("register -s /no/source@1 -t /no/target@2" + t);
    EXPECT_EQ(both.exit_code, 2) << both.output;
    EXPECT_NE(both.output.find("/no/source@1"), std::string::npos) << both.output;
    EXPECT_EQ(both.output.find("/no/target@2"), std::string::npos) << both.output;
    const auto target = RunCli("register -s " + good + " -t /no/target@2" + t);
    EXPECT_EQ(target.exit_code, 2) << target.output;
    EXPECT_NE(target.output.find("/no/target@2"), std::string::npos) << target.output;
    EXPECT_EQ(target.output.find("zeroreg_no_assets"), std::string::npos) << target.output;
    const auto gt = RunCli("register -s " + good + " -t " + good + " --gt /no/gt.txt" + t);
    EXPECT_EQ(gt.exit_code, 2) << gt.output;
    EXPECT_NE(gt.output.find("/no/gt.txt"), std::string::npos) << gt.output;
    EXPECT_EQ(gt.output.find("zeroreg_no_assets"), std::string::npos) << gt.output;
    const auto models = RunCli("register -s " + good + " -t " + good + t);
    EXPECT_EQ(models.exit_code, 2) << models.output;
    EXPECT_NE(models.output.find("zeroreg_no_assets"), std::string::npos) << models.output;
  }
}

}  // namespace
}  // namespace zeroreg
