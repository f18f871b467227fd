// Every bad input raises InputError whose message names the file and the problem.
#include <gtest/gtest.h>

#include "io/io_test_util.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using testing_io::ExpectInputError;
using testing_io::MatrixText;
using testing_io::SomePose;
using testing_io::TempDir;
using testing_io::WriteColor;
using testing_io::WriteDepth;
using testing_io::WriteText;

const Intrinsics kK{500, 500, 2, 1.5, 0, 0};

// ---- images -------------------------------------------------------------------------------------

TEST(IoBadInput, MissingColourImage) {
  TempDir dir;
  ExpectInputError([&] { ReadColorImage(dir.File("nothere.color.jpg")); },
                   {"nothere.color.jpg", "not found"});
}

TEST(IoBadInput, MissingDepthImage) {
  TempDir dir;
  WriteColor(dir.File("c.png"), 4, 3);
  ExpectInputError([&] { LoadView(dir.File("c.png"), dir.File("gone.depth.png"), kK, 1000); },
                   {"gone.depth.png", "not found"});
}

TEST(IoBadInput, CorruptColourImage) {
  TempDir dir;
  WriteText(dir.File("broken.jpg"), "this is not a JPEG");
  ExpectInputError([&] { ReadColorImage(dir.File("broken.jpg")); },
                   {"broken.jpg", "cannot be decoded"});
}

TEST(IoBadInput, CorruptDepthImage) {
  TempDir dir;
  WriteText(dir.File("broken.png"), "\x89PNG\r\n\x1a\n truncated");
  ExpectInputError([&] { ReadDepthImage(dir.File("broken.png"), 1000); },
                   {"broken.png", "truncated PNG"});
}

TEST(IoBadInput, ColourDepthSizeMismatch) {
  TempDir dir;
  WriteColor(dir.File("c.png"), 8, 6);
  WriteDepth(dir.File("d.png"), 4, 3, 1000);
  ExpectInputError([&] { LoadView(dir.File("c.png"), dir.File("d.png"), kK, 1000); },
                   {"c.png", "d.png", "8x6", "4x3", "same size"});
}

TEST(IoBadInput, DepthNot16Bit) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir.File("d8.png"), cv::Mat(3, 4, CV_8UC1, cv::Scalar(7))));
  ExpectInputError([&] { ReadDepthImage(dir.File("d8.png"), 1000); },
                   {"d8.png", "8-bit", "16-bit single-channel"});
}

TEST(IoBadInput, DepthMultiChannel) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir.File("d3.png"), cv::Mat(3, 4, CV_16UC3, cv::Scalar(7, 7, 7))));
  ExpectInputError([&] { ReadDepthImage(dir.File("d3.png"), 1000); },
                   {"d3.png", "3 channel", "16-bit single-channel"});
}

TEST(IoBadInput, AllInvalidDepth) {
  TempDir dir;
  WriteColor(dir.File("c.png"), 4, 3);
  WriteDepth(dir.File("zeros.png"), 4, 3, 0);
  WriteDepth(dir.File("saturated.png"), 4, 3, 65535);
  for (const char* name : {"zeros.png", "saturated.png"}) {
    ExpectInputError([&] { LoadView(dir.File("c.png"), dir.File(name), kK, 1000); },
                     {name, "no valid pixel"});
  }
}

TEST(IoBadInput, BadDepthScale) {
  TempDir dir;
  WriteDepth(dir.File("d.png"), 4, 3, 1000);
  ExpectInputError([&] { ReadDepthImage(dir.File("d.png"), 0.0); }, {"d.png", "depth_scale"});
  DatasetOptions options;
  options.depth_scale = -5;
  WriteColor(dir.File("frame-000000.color.png"), 4, 3);
  WriteText(dir.File("camera-intrinsics.txt"), "1 0 0\n0 1 0\n0 0 1\n");
  ExpectInputError([&] { OpenDataset(dir.path().string(), options); }, {"depth_scale", "> 0"});
}

// ---- intrinsics ---------------------------------------------------------------------------------

TEST(IoBadInput, IntrinsicsMissing) {
  TempDir dir;
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("camera-intrinsics.txt"), 640, 480); },
                   {"camera-intrinsics.txt", "not found"});
}

TEST(IoBadInput, IntrinsicsWrongCount) {
  TempDir dir;
  WriteText(dir.File("K8.txt"), "585 0 320\n0 585 240\n0 0\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("K8.txt"), 640, 480); },
                   {"K8.txt", "8 numbers", "expected 9"});
}

TEST(IoBadInput, IntrinsicsNotANumber) {
  TempDir dir;
  WriteText(dir.File("Kword.txt"), "585 0 320\n0 fx 240\n0 0 1\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("Kword.txt"), 640, 480); },
                   {"Kword.txt", "line 2", "'fx' is not a number"});
}

TEST(IoBadInput, IntrinsicsNonFinite) {
  TempDir dir;
  WriteText(dir.File("Knan.txt"), "585 0 nan\n0 585 240\n0 0 1\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("Knan.txt"), 640, 480); },
                   {"Knan.txt", "non-finite"});
}

TEST(IoBadInput, IntrinsicsNonPositiveFocal) {
  TempDir dir;
  WriteText(dir.File("Kzero.txt"), "0 0 320\n0 585 240\n0 0 1\n");
  WriteText(dir.File("Kneg.txt"), "585 0 320\n0 -585 240\n0 0 1\n");
  for (const char* name : {"Kzero.txt", "Kneg.txt"}) {
    ExpectInputError([&] { ReadIntrinsicsFile(dir.File(name), 640, 480); },
                     {name, "focal length", "fx > 0 and fy > 0"});
  }
}

TEST(IoBadInput, IntrinsicsNotACameraMatrix) {
  TempDir dir;
  WriteText(dir.File("Krow.txt"), "585 0 320\n0 585 240\n0 0 0\n");
  ExpectInputError([&] { ReadIntrinsicsFile(dir.File("Krow.txt"), 640, 480); },
                   {"Krow.txt", "0 0 1"});
}

TEST(IoBadInput, DatasetWithoutIntrinsics) {
  TempDir dir;
  WriteColor(dir.File("frames/frame-000000.color.jpg"), 4, 3);
  ExpectInputError([&] { OpenDataset(dir.path().string()); },
                   {"camera-intrinsics.txt", "not found"});
}

// ---- poses --------------------------------------------------------------------------------------

TEST(IoBadInput, PoseWrongCount) {
  TempDir dir;
  std::string text = MatrixText(SomePose());
  text = text.substr(0, text.rfind(' ', text.size() - 3));  // drop the last number
  WriteText(dir.File("frame-000001.pose.txt"), text);
  ExpectInputError([&] { ReadPoseFile(dir.File("frame-000001.pose.txt")); },
                   {"frame-000001.pose.txt", "15 numbers", "expected 16"});
}

TEST(IoBadInput, PoseNonFinite) {
  TempDir dir;
  Transform T = SomePose();
  T(1, 3) = std::numeric_limits<double>::quiet_NaN();
  WriteText(dir.File("nan.pose.txt"), MatrixText(T));
  ExpectInputError([&] { ReadPoseFile(dir.File("nan.pose.txt")); },
                   {"nan.pose.txt", "non-finite", "row 2, column 4"});
}

TEST(IoBadInput, PoseNotRigid) {
  TempDir dir;
  Transform scaled = SomePose();
  scaled.topLeftCorner<3, 3>() *= 1.1;
  WriteText(dir.File("scaled.pose.txt"), MatrixText(scaled));
  Transform mirrored = SomePose();
  mirrored.row(0) *= -1.0;  // det -1 but orthonormal
  mirrored(3, 3) = 1.0;
  WriteText(dir.File("mirrored.pose.txt"), MatrixText(mirrored));
  for (const char* name : {"scaled.pose.txt", "mirrored.pose.txt"}) {
    ExpectInputError([&] { ReadPoseFile(dir.File(name)); }, {name, "not rigid"});
  }
}

TEST(IoBadInput, PoseBadLastRow) {
  TempDir dir;
  Transform T = SomePose();
  T(3, 0) = 0.5;
  WriteText(dir.File("row.pose.txt"), MatrixText(T));
  ExpectInputError([&] { ReadPoseFile(dir.File("row.pose.txt")); },
                   {"row.pose.txt", "bad last row", "0 0 0 1"});
}

TEST(IoBadInput, DatasetFrameWithBadPose) {
  TempDir dir;
  WriteColor(dir.File("frame-000003.color.png"), 4, 3);
  WriteDepth(dir.File("frame-000003.depth.png"), 4, 3, 1000);
  WriteText(dir.File("frame-000003.pose.txt"), "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  WriteText(dir.File("camera-intrinsics.txt"), "10 0 2\n0 10 1.5\n0 0 1\n");
  const auto dataset = OpenDataset(dir.path().string());
  ExpectInputError([&] { dataset->LoadFrame(3); }, {"frame-000003.pose.txt", "expected 16"});
  ExpectInputError([&] { dataset->LoadFrame(4); }, {"frame id 4", "not in the dataset"});
}

// ---- logs ---------------------------------------------------------------------------------------

const char* kGoodEntry = "0\t 1\t 60\t\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";

TEST(IoBadInput, LogBadHeader) {
  TempDir dir;
  WriteText(dir.File("gt.log"),
            std::string(kGoodEntry) + "0 2\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  ExpectInputError([&] { ReadLogFile(dir.File("gt.log")); },
                   {"gt.log", "line 6", "malformed header", "'i j n'"});
}

TEST(IoBadInput, LogShortRow) {
  TempDir dir;
  WriteText(dir.File("est.log"), "0 1 60\n1 0 0 0\n0 1 0\n0 0 1 0\n0 0 0 1\n");
  ExpectInputError([&] { ReadLogFile(dir.File("est.log")); },
                   {"est.log", "line 3", "holds 3 values", "expected 4"});
}

TEST(IoBadInput, LogNotANumber) {
  TempDir dir;
  WriteText(dir.File("est.log"), "0 1 60\n1 0 0 0\n0 1 0 0\n0 0 1 abc\n0 0 0 1\n");
  ExpectInputError([&] { ReadLogFile(dir.File("est.log")); },
                   {"est.log", "line 4", "'abc' is not a finite number"});
}

TEST(IoBadInput, LogTruncated) {
  TempDir dir;
  WriteText(dir.File("est.log"), std::string(kGoodEntry) + "3 4 60\n1 0 0 0\n");
  ExpectInputError([&] { ReadLogFile(dir.File("est.log")); },
                   {"est.log", "line 7", "ends inside an entry"});
}

TEST(IoBadInput, LogMissing) {
  TempDir dir;
  ExpectInputError([&] { ReadLogFile(dir.File("none.log")); }, {"none.log", "not found"});
}

TEST(IoBadInput, InfoBadRow) {
  TempDir dir;
  WriteText(dir.File("gt.info"),
            "0 1 60\n1 0 0 0 0 0\n0 1 0 0 0 0\n0 0 1 0 0 0\n0 0 0 1 0 0\n0 0 0 0 1\n0 0 0 0 0 1\n");
  ExpectInputError([&] { ReadInfoFile(dir.File("gt.info")); },
                   {"gt.info", "line 6", "holds 5 values", "expected 6"});
}

// ---- TUM lists ----------------------------------------------------------------------------------

TEST(IoBadInput, TumMalformedLines) {
  TempDir dir;
  WriteText(dir.File("rgb.txt"), "# c\n1.0 rgb/1.png\n1.1rgb/2.png\n");
  WriteText(dir.File("depth.txt"), "1.0 depth/1.png\n");
  ExpectInputError([&] { OpenDataset(dir.path().string()); },
                   {"rgb.txt", "line 3", "'timestamp path'"});
  WriteText(dir.File("rgb.txt"), "1.0 rgb/1.png\n");
  WriteText(dir.File("groundtruth.txt"), "# t\n1.0 0 0 0 0 0 0\n");
  ExpectInputError([&] { OpenDataset(dir.path().string()); },
                   {"groundtruth.txt", "line 2", "8 finite numbers"});
}

// ---- descriptors and specs ----------------------------------------------------------------------

TEST(IoBadInput, DescriptorUnknownKey) {
  TempDir dir;
  WriteText(dir.File("scan.json"),
            R"({"name": "s", "views": [{"color": "c.png", "depth": "d.png", "depth_sacle": 1000,
                "intrinsics": {"fx": 1, "fy": 1, "cx": 0, "cy": 0}}]})");
  ExpectInputError([&] { ReadScanDescriptor(dir.File("scan.json")); },
                   {"scan.json", "views[0]", "unknown key 'depth_sacle'"});
  WriteText(dir.File("top.json"), R"({"name": "s", "view": []})");
  ExpectInputError([&] { ReadScanDescriptor(dir.File("top.json")); },
                   {"top.json", "unknown key 'view'"});
}

TEST(IoBadInput, DescriptorInvalidJson) {
  TempDir dir;
  WriteText(dir.File("bad.json"), R"({"name": "s", "views": [)");
  ExpectInputError([&] { LoadScan(dir.File("bad.json")); }, {"bad.json", "not valid JSON"});
}

TEST(IoBadInput, DescriptorBadFields) {
  TempDir dir;
  WriteText(dir.File("noK.json"), R"({"views": [{"color": "c.png", "depth": "d.png"}]})");
  ExpectInputError([&] { ReadScanDescriptor(dir.File("noK.json")); },
                   {"noK.json", "'intrinsics' or 'intrinsics_file'"});
  WriteText(dir.File("pose.json"),
            R"({"views": [{"color": "c.png", "depth": "d.png", "T_scan_camera": [1, 0, 0],
                "intrinsics": {"fx": 1, "fy": 1, "cx": 0, "cy": 0}}]})");
  ExpectInputError([&] { ReadScanDescriptor(dir.File("pose.json")); },
                   {"pose.json", "'T_scan_camera'", "16 numbers"});
  WriteText(dir.File("noviews.json"), R"({"name": "s", "views": []})");
  ExpectInputError([&] { ReadScanDescriptor(dir.File("noviews.json")); },
                   {"noviews.json", "at least one view"});
  WriteText(dir.File("cloud.json"),
            R"({"views": [{"color": "c.png", "depth": "d.png",
                "intrinsics": {"fx": 1, "fy": 1, "cx": 0, "cy": 0}}], "cloud": "missing.ply"})");
  WriteColor(dir.File("c.png"), 4, 3);
  WriteDepth(dir.File("d.png"), 4, 3, 1000);
  ExpectInputError([&] { LoadScan(dir.File("cloud.json")); }, {"missing.ply", "not found"});
}

TEST(IoBadInput, BadScanSpecs) {
  TempDir dir;
  const std::string root = dir.path().string();
  ExpectInputError([&] { LoadScan(root + "/nothing@3"); }, {"nothing", "not found"});
  ExpectInputError([&] { LoadScan(root + "@x"); }, {"'x'", "DIR@N"});
  ExpectInputError([&] { LoadScan(root); }, {root, "no scan.json"});
  WriteText(dir.File("notes.txt"), "hello");
  ExpectInputError([&] { LoadScan(dir.File("notes.txt")); },
                   {"notes.txt", "unrecognised scan specification"});
  ExpectInputError([&] { LoadScan(root + "@0"); }, {root, "unrecognised dataset layout"});
  ExpectInputError([&] { OpenDataset(root + "/missing"); }, {"missing", "not found"});
}

}  // namespace
}  // namespace zeroreg
