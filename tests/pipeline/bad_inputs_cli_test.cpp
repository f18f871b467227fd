// Bad or unusual input to the command line. Each case asserts the exit code (2 = bad
// input, never 3 = internal error) and that the message names the file or argument at fault.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "pipeline/cli_fixture.hpp"
#include "test_paths.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::CliBadInput;
using testing::RedkitchenDir;
using testing::RunCli;

// A scan.json for frame `id` of the fixture's folder, with `intrinsics` as its intrinsics object.
std::string ScanJson(const std::string& id, const std::string& intrinsics) {
  return R"({"views": [{"color": "frame-)" + id + R"(.color.jpg", "depth": "frame-)" + id +
         R"(.depth.png", "intrinsics": )" + intrinsics + "}]}";
}
const char* kIntrinsics = R"({"fx": 585, "fy": 585, "cx": 320, "cy": 240})";

// ---- JSON numbers and types ---------------------------------------------------------------------

TEST_F(CliBadInput, NumberOverflowInScanJson) {
  Write("src.json", ScanJson("000020", R"({"fx": 1e400, "fy": 585, "cx": 320, "cy": 240})"));
  ExpectClearError(RunCli("register -s '" + Path("src.json") + "' -t '" + Path("") + "@0'"),
                   "src.json", "number overflow");
}

TEST_F(CliBadInput, IntrinsicsWidthMustBeAWholeNumberOfPixels) {
  for (const char* width : {"1e30", "-640", "640.9", "true"}) {
    Write("src.json", ScanJson("000020", std::string(R"({"fx": 585, "fy": 585, "cx": 320, )") +
                                             R"("cy": 240, "width": )" + width + "}"));
    ExpectClearError(RunCli("register -s '" + Path("src.json") + "' -t '" + Path("") + "@0'"),
                     "src.json", "'width' is");
  }
}

TEST_F(CliBadInput, ConfigIntegersDoNotWrap) {
  Write("config.json", R"({"ransac": {"max_iterations": 4294967297}})");
  ExpectClearError(Run("--config '" + Path("config.json") + "'"), "config.json",
                   "ransac.max_iterations is 4294967297; expected an integer in [1, 10000000]");
  ExpectClearError(Run("--set ransac.max_iterations=99999999999"),
                   "--set ransac.max_iterations=99999999999", "expected an integer");
  ExpectClearError(Run("--set seed=-3"), "--set seed=-3", "expected an integer in [0, ");
  ExpectClearError(Run("--seed -3"), "--seed -3", "expected an integer");
}

TEST_F(CliBadInput, ConfigValuesOutOfRangeOrOfTheWrongType) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"ransac": {"max_iterations": 0}})", "ransac.max_iterations is 0"},
      {R"({"ransac": {"max_iterations": true}})", "ransac.max_iterations is true"},
      {R"({"ransac": {"max_iterations": 2.7}})", "ransac.max_iterations is 2.7"},
      {R"({"refine": {"voxel_m": 0}})", "refine.voxel_m is 0"},
      {R"({"objects": {"min_views": 0}})", "objects.min_views is 0"},
      {R"({"object_match": {"restarts": -1}})", "object_match.restarts is -1"},
      {R"({"match": {"sinkhorn": {"iterations": 0}}})", "match.sinkhorn.iterations is 0"},
      {R"({"depth": {"min_m": 9}})", "depth.min_m (9) must be below depth.max_m"},
  };
  for (const auto& [config, message] : cases) {
    Write("config.json", config);
    ExpectClearError(Run("--config '" + Path("config.json") + "'"), "config.json", message);
  }
}

TEST_F(CliBadInput, SetMessagesSayWhatWasGiven) {
  const auto r = Run("--set X=abc");
  ExpectClearError(r, "--set X=abc", "unknown key 'X'");
  EXPECT_EQ(r.output.find("ransac.seed"), std::string::npos) << r.output;  // no such key
  ExpectClearError(Run("--set ransac.inlier_threshold_m=1e999"),
                   "--set ransac.inlier_threshold_m=1e999", "out of the range");
  ExpectClearError(Run("--set ransac.inlier_threshold_m=abc"),
                   "--set ransac.inlier_threshold_m=abc: ransac.inlier_threshold_m is \"abc\"",
                   "expected a number > 0");
  ExpectClearError(Run("--set match.sinkhorn.temperature=0"), "match.sinkhorn.temperature",
                   "expected a number > 0");
}

// ---- files that are folders or FIFOs ------------------------------------------------------------

// inference.engine: an unknown engine, a thread count out of range, and (in a build
// without ONNX Runtime) the engines and backends that need it, each named.
TEST_F(CliBadInput, InferenceEngineAndSamNamed) {
  ExpectClearError(Run("--set inference.engine=tensorrt"), "inference.engine",
                   "expected one of: auto, onnxruntime, opencv");
  ExpectClearError(Run("--set inference.threads=0"), "inference.threads", "expected an integer");
  ExpectClearError(Run("--set segmenter.backend=sam2"), "segmenter.backend", "sam");
#ifndef ZEROREG_TEST_WITH_ONNXRUNTIME
  ExpectClearError(Run("--set inference.engine=onnxruntime"), "inference.engine",
                   "built without ONNX Runtime");
  ExpectClearError(Run("--set segmenter.backend=sam"), "segmenter.backend", "needs ONNX Runtime");
#endif
}

TEST_F(CliBadInput, ConfigThatIsAFolder) {
  fs::create_directories(Path("config-folder"));
  ExpectClearError(Run("--config '" + Path("config-folder") + "'"), "config-folder",
                   "not a regular file");
}

TEST_F(CliBadInput, FifosAreRefusedNotWaitedOn) {
  ASSERT_EQ(::mkfifo(Path("fifo").c_str(), 0600), 0);
  ExpectClearError(RunCli("register -s '" + Path("") + "@20' -t '" + Path("") + "@0' --config '" +
                              Path("fifo") + "'",
                          60),
                   "fifo", "not a regular file");
  ExpectClearError(RunCli("eval pairs --data '" + Path("") + "' --gap 20 --pairs '" + Path("fifo") +
                              "' --out '" + Path("eval") + "'",
                          60),
                   "fifo", "not a regular file");
}

TEST_F(CliBadInput, DetectionsFileThatIsAFolder) {
  fs::create_directories(Path("detections/frame-000020.color.json"));
  ExpectClearError(
      Run("--set detector.backend=file --set detector.detections_dir='" + Path("detections") + "'"),
      "frame-000020.color.json", "not a regular file");
}

// ---- images
// ---------------------------------------------------------------------------------------

TEST_F(CliBadInput, TruncatedJpeg) {
  fs::resize_file(Path("frame-000020.color.jpg"),
                  fs::file_size(Path("frame-000020.color.jpg")) / 2);
  ExpectClearError(Run(), "frame-000020.color.jpg", "truncated JPEG");
}

TEST_F(CliBadInput, HugePngIsRefusedBeforeDecoding) {
  // A real 16-bit PNG whose header is then made to claim 20000 x 20000 pixels.
  std::string bytes;
  {
    std::ifstream in(Path("frame-000020.depth.png"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  for (int offset : {16, 20}) {
    bytes[offset] = 0, bytes[offset + 1] = 0, bytes[offset + 2] = 0x4E, bytes[offset + 3] = 0x20;
  }
  Write("frame-000020.depth.png", bytes);
  ExpectClearError(Run(), "frame-000020.depth.png", "20000x20000 pixels, more than the limit");
}

TEST_F(CliBadInput, MissingColourIsNotAnUnknownFrame) {
  fs::remove(Path("frame-000020.color.jpg"));
  ExpectClearError(Run(), "frame-000020.color.jpg", "colour image not found");
}

// ---- options
// --------------------------------------------------------------------------------------

TEST_F(CliBadInput, ExplicitAssetsFolderMustExist) {
  ExpectClearError(Run("--assets '" + Path("no-such-assets") + "'"), "no-such-assets",
                   "does not exist");
}

TEST_F(CliBadInput, OutputFolderIsCheckedBeforeRegistering) {
  const auto r = Run("--out '" + Path("no-such-folder/result.json") + "'");
  ExpectClearError(r, "--out", "does not exist");
  EXPECT_EQ(r.output.find("verdict"), std::string::npos) << "registered first:\n" << r.output;
}

TEST_F(CliBadInput, ReadableRangeMessages) {
  const auto r = RunCli("eval pairs --data '" + Path("") + "' --gap 0 --out '" + Path("e") + "'");
  ExpectClearError(r, "--gap", "expected an integer >= 1");
  EXPECT_EQ(r.output.find("1797"), std::string::npos) << r.output;
}

TEST_F(CliBadInput, FuseParameters) {
  const std::string fuse = "fuse -d '" + Path("") + "' -o '" + Path("fragment") + "' ";
  ExpectClearError(RunCli(fuse + "-f 0,20 --views 0"), "--views", "expected an integer >= 1");
  ExpectClearError(RunCli(fuse + "-f 0,20 --voxel -0.01"), "--voxel", "expected a voxel size");
  ExpectClearError(RunCli(fuse + "-f 0,20 --voxel 0"), "--voxel", "expected a voxel size");
  ExpectClearError(RunCli(fuse + "-f 0,20 --voxel 0.0001"), "--voxel", "expected a voxel size");
  const auto start = std::chrono::steady_clock::now();
  ExpectClearError(RunCli(fuse + "-f 0-999999999"), "--frames 0-999999999", "frame 1 is not in");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST_F(CliBadInput, FuseReportsTheViewsItWrote) {
  const auto r = RunCli("fuse -d '" + Path("") + "' -o '" + Path("fragment") +
                        "' -f 0,20 --views 5 --voxel 0.05");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(2 frames, 2 views)"), std::string::npos) << r.output;
  const auto scan = nlohmann::json::parse(std::ifstream(Path("fragment/scan.json")));
  EXPECT_EQ(scan["views"].size(), 2u);
}

TEST_F(CliBadInput, ReportOnAResultOfTheWrongType) {
  fs::create_directories(Path("run"));
  Write("run/result.json",
        R"({"source": "a", "target": "b", "seed": 0, "config": {},
            "result": {"valid": "yes", "reason": 3, "timings_ms": {"total": "slow"},
                       "T_target_source": "identity", "counts": []}})");
  const auto r = RunCli("report '" + Path("run") + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(Path("run")), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

// ---- bring-your-own-model files: keyed by the image file's stem ---------------------------------

// Two scan.json files whose views both have index 0: the detections of each must be its own.
TEST_F(CliBadInput, DetectionFilesAreKeyedByImageStemNotViewIndex) {
  Write("src.json", ScanJson("000020", kIntrinsics));
  Write("tgt.json", ScanJson("000000", kIntrinsics));
  fs::create_directories(Path("detections"));
  const std::string cup = R"(, "detections": [{"box": [10, 10, 200, 200], "label": "cup"}]})";
  const std::string run = "register -s '" + Path("src.json") + "' -t '" + Path("tgt.json") +
                          "' --set detector.backend=file --set detector.detections_dir='" +
                          Path("detections") + "'";
  // The file the view index would name is not read ...
  Write("detections/0.json", R"({"detections": []})");
  ExpectClearError(RunCli(run), "frame-0000", "not found");
  // ... each image's own is, "image" check included.
  Write("detections/frame-000020.color.json", R"({"image": "frame-000020.color.jpg")" + cup);
  Write("detections/frame-000000.color.json", R"({"image": "frame-000000.color.jpg")" + cup);
  const auto r = RunCli(run);
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
  EXPECT_EQ(r.output.find("error:"), std::string::npos) << r.output;
}

TEST_F(CliBadInput, TooManyDetections) {
  fs::create_directories(Path("detections"));
  std::string boxes;
  for (int i = 0; i < 1001; ++i)
    boxes += std::string(i ? ", " : "") + R"({"box": [1, 1, 9, 9], "label": "cup"})";
  Write("detections/frame-000020.color.json", R"({"detections": [)" + boxes + "]}");
  ExpectClearError(
      Run("--set detector.backend=file --set detector.detections_dir='" + Path("detections") + "'"),
      "frame-000020.color.json", "more than detector.max_detections (1000)");
}

// ---- results on paths that are not UTF-8
// ----------------------------------------------------------

TEST_F(CliBadInput, ResultOnANonUtf8PathIsWritten) {
  const fs::path odd = dir_ / "bad\xffname";
  fs::create_directories(odd);
  for (const auto& entry : fs::directory_iterator(dir_)) {
    if (entry.is_regular_file()) fs::copy_file(entry.path(), odd / entry.path().filename());
  }
  const auto r = RunCli("register -s '" + odd.string() + "@20' -t '" + odd.string() +
                        "@0' --out '" + Path("r.json") + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto result = nlohmann::json::parse(std::ifstream(Path("r.json")));
  EXPECT_NE(result["source"].get<std::string>().find("bad\xEF\xBF\xBDname"), std::string::npos);
  EXPECT_TRUE(result["result"]["valid"].get<bool>());
}

// --prior: a motion prior file as --gt's; the result records it, and one that is no rigid
// transform, or a tolerance that is not positive, is refused by name.
TEST_F(CliBadInput, MotionPriorFromAFile) {
  // Frame 20 of redkitchen is 6.4 deg and 14 cm from frame 0 at most (data MANIFEST): the
  // identity as a prior with 20 deg and 0.5 m of tolerance holds the right pose.
  Write("prior.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  const auto good = Run("--prior '" + Path("prior.txt") +
                        "' --prior-max-rotation-deg 20 --prior-max-translation-m 0.5 --out '" +
                        Path("result.json") + "'");
  EXPECT_EQ(good.exit_code, 0) << good.output;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(Path("result.json")));
  EXPECT_TRUE(j["result"]["valid"].get<bool>());
  EXPECT_EQ(j["prior"]["max_rotation_deg"].get<double>(), 20.0);
  EXPECT_EQ(j["prior"]["max_translation_m"].get<double>(), 0.5);

  // With 1 cm of tolerance the identity does not hold it: not valid, and the reason says why.
  const auto tight = Run("--prior '" + Path("prior.txt") + "' --prior-max-translation-m 0.01");
  EXPECT_EQ(tight.exit_code, 1) << tight.output;
  EXPECT_NE(tight.output.find("from the motion prior"), std::string::npos) << tight.output;

  Write("scaled.txt", "2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n");
  const auto scaled = Run("--prior '" + Path("scaled.txt") + "'");
  EXPECT_EQ(scaled.exit_code, 2) << scaled.output;
  EXPECT_NE(scaled.output.find("scaled.txt"), std::string::npos) << scaled.output;
  ExpectClearError(Run("--prior '" + Path("missing.txt") + "'"), "missing.txt", "");
  ExpectClearError(Run("--prior '" + Path("prior.txt") + "' --prior-max-rotation-deg 0"),
                   "--prior-max-rotation-deg", "expected a positive number");
  // A tolerance without a prior, or a prior with the baselines (which take none), is refused.
  ExpectClearError(Run("--prior-max-translation-m 0.2"), "--prior-max-translation-m",
                   "requires --prior");
  ExpectClearError(Run("--prior '" + Path("prior.txt") + "' --baseline sift"), "--prior",
                   "excludes --baseline");
}

}  // namespace
}  // namespace zeroreg
