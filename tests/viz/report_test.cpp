// `zeroreg report` (src/viz/report.hpp): pages for a real `register --out-dir` run and for a small
// eval folder written with the runner's own functions, opened in headless Chromium to check that
// the tables, the sorting and the embedded pictures are there once the page is loaded.
#include "viz/report.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <open3d/geometry/PointCloud.h>
#include <open3d/io/PointCloudIO.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>

#include "eval/records.hpp"
#include "eval/session.hpp"
#include "test_paths.hpp"
#include "viz/ply.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
const char* kChromium = "/usr/bin/chromium";

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int CountOccurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The DOM of `url` after its scripts ran, as headless Chromium serialises it.
std::string DumpDom(const std::string& url, const fs::path& profile) {
  const std::string command =
      std::string("timeout 90 ") + kChromium +
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir='" +
      profile.string() + "' --dump-dom '" + url + "' 2>/dev/null";
  std::string dom;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return dom;
  char buffer[65536];
  size_t n = 0;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) dom.append(buffer, n);
  pclose(pipe);
  return dom;
}

// The rows of the table with id `id` in `html`: the text between its <tbody> and </tbody>.
std::string TableBody(const std::string& html, const std::string& id) {
  const size_t table = html.find("<table class=\"sortable\" id=\"" + id + "\"");
  if (table == std::string::npos) return "";
  const size_t begin = html.find("<tbody>", table), end = html.find("</tbody>", table);
  if (begin == std::string::npos || end == std::string::npos) return "";
  return html.substr(begin, end - begin);
}

// Number of <img> elements whose source is an embedded data URI.
int DataImages(const std::string& html) { return CountOccurrences(html, "<img src=\"data:image/"); }

void ExpectNoNetworkReferences(const std::string& html) {
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("src=\"//"), std::string::npos);  // protocol-relative URLs
}

// The values of the first column ("#", the pairs.jsonl index) of each row, in page order.
std::vector<int> RowOrder(const std::string& body) {
  std::vector<int> order;
  static const std::regex first_cell("<tr><td class=\"num\" data-value=\"([0-9]+)\"");
  for (std::sregex_iterator it(body.begin(), body.end(), first_cell), end; it != end; ++it) {
    order.push_back(std::stoi((*it)[1]));
  }
  return order;
}

std::string Base64Decode(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  int bits = 0, value = 0;
  for (char c : text) {
    const size_t k = alphabet.find(c);
    if (k == std::string::npos) break;  // '=' padding
    value = (value << 6) | static_cast<int>(k);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((value >> bits) & 0xff));
    }
  }
  return out;
}

fs::path TempDir(const std::string& what) {
  const fs::path dir =
      fs::temp_directory_path() / ("zeroreg_report_" + std::to_string(::getpid()) + "_" + what);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(ReportHelpers, Base64AndEscaping) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xff\x00\x10", 3)), "/wAQ");
  EXPECT_EQ(HtmlEscape("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;");
}

TEST(ReportHelpers, LargePicturesAreDownscaledAndReencoded) {
  const fs::path dir = TempDir("images");
  cv::Mat big(900, 3000, CV_8UC3);
  cv::randu(big, 0, 255);  // noise: a large PNG
  cv::imwrite((dir / "big.png").string(), big);
  cv::Mat small(40, 60, CV_8UC3, cv::Scalar(0, 128, 255));
  cv::imwrite((dir / "small.png").string(), small);
  ReportConfig config;
  config.max_image_width = 600;
  const std::string big_uri = ImageDataUri((dir / "big.png").string(), config);
  ASSERT_EQ(big_uri.rfind("data:image/jpeg;base64,", 0), 0u);
  const std::string small_uri = ImageDataUri((dir / "small.png").string(), config);
  // A small PNG is embedded byte for byte.
  EXPECT_EQ(small_uri, "data:image/png;base64," + Base64Encode(ReadText(dir / "small.png")));
  // The big one is a JPEG 600 px wide with the same aspect ratio.
  const std::string jpeg = Base64Decode(big_uri.substr(big_uri.find(',') + 1));
  const cv::Mat decoded = cv::imdecode(
      cv::Mat(1, static_cast<int>(jpeg.size()), CV_8UC1, const_cast<char*>(jpeg.data())),
      cv::IMREAD_COLOR);
  EXPECT_EQ(decoded.cols, 600);
  EXPECT_EQ(decoded.rows, 180);
  EXPECT_LT(big_uri.size(), ReadText(dir / "big.png").size());
  EXPECT_EQ(ImageDataUri((dir / "missing.png").string(), config), "");
  fs::remove_all(dir);
}

TEST(ReportErrors, UnknownFolderIsAnInputError) {
  const fs::path dir = TempDir("empty");
  try {
    BuildReportHtml(dir.string());
    FAIL() << "no error for a folder without results";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("result.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(BuildReportHtml((dir / "absent").string()), InputError);
  std::ofstream(dir / "result.json") << "{ not json";
  EXPECT_THROW(BuildReportHtml(dir.string()), InputError);
  fs::remove_all(dir);
  const auto r = testing::RunCli("report '" + (dir / "absent").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("absent"), std::string::npos) << r.output;
}

// ---- eval folder -------------------------------------------------------------------------------

// Three frame pairs written with the eval runner's own functions (pairs.jsonl, summary.json,
// summary.md), the second with per-pair pictures in the folder PairPictureFolder names.
class EvalReport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = TempDir("eval");
    RunInfo info;
    info.protocol = "pairs";
    info.method = "zeroreg";
    info.command = "zeroreg eval pairs --limit 3";
    std::vector<PairRecord> records;
    const double rotation_deg[3] = {2.5, 40.0, 0.7};
    const int source_ids[3] = {20, 30, 40};
    for (int k = 0; k < 3; ++k) {
      PairTask task;
      task.benchmark = "frames-g20";
      task.scene = "7scenes-redkitchen";
      task.target_id = source_ids[k] - 20;
      task.source_id = source_ids[k];
      info.tasks.push_back(task);
      PairRecord r;
      r.key = task.Key();
      r.benchmark = task.benchmark;
      r.scene = task.scene;
      r.method = "zeroreg";
      r.target_id = task.target_id;
      r.source_id = task.source_id;
      r.valid = k != 1;
      r.reason = k != 1 ? "ok" : "too few inliers";
      r.rotation_error_deg = rotation_deg[k];
      r.translation_error_m = 0.01 * (k + 1);
      r.inlier_ratio = 0.5;
      r.num_correspondences = 100 + k;
      r.num_inliers = 50 + k;
      r.time_ms = 1000;
      records.push_back(r);
    }
    WritePairsJsonl((dir_ / "pairs.jsonl").string(), records);
    WriteSummary(dir_.string(), info, info.tasks, records);
    const fs::path pictures = dir_ / PairPictureFolder("frames-g20", "7scenes-redkitchen", 10, 30);
    fs::create_directories(pictures);
    for (const char* name : {"correspondences-view0.png", "registered-view0.png"}) {
      cv::imwrite((pictures / name).string(), cv::Mat(30, 50, CV_8UC3, cv::Scalar(40, 90, 200)));
    }
    html_ = BuildReportHtml(dir_.string());
    std::ofstream(dir_ / "report.html") << html_;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static fs::path dir_;
  static std::string html_;
};
fs::path EvalReport::dir_;
std::string EvalReport::html_;

TEST_F(EvalReport, PageHasSummaryPairsAndThePairsPictures) {
  // The summary table of summary.md: its header and the one "frames" row.
  EXPECT_NE(html_.find("<table class=\"summary\">"), std::string::npos);
  EXPECT_NE(html_.find("RE acc 5 / 10 / 45 deg (%)"), std::string::npos);
  EXPECT_EQ(CountOccurrences(TableBody(html_, "pairs"), "<tr>"), 3);
  EXPECT_EQ(RowOrder(TableBody(html_, "pairs")), (std::vector<int>{0, 1, 2}));
  EXPECT_NE(html_.find("too few inliers"), std::string::npos);
  // Only pair #1 has pictures: two embedded images under its section, linked from its row.
  EXPECT_EQ(DataImages(html_), 2);
  EXPECT_NE(html_.find("<section id=\"pair-1\">"), std::string::npos);
  EXPECT_EQ(html_.find("<section id=\"pair-0\">"), std::string::npos);
  EXPECT_NE(html_.find("href=\"#pair-1\""), std::string::npos);
  EXPECT_EQ(html_.find("id=\"no-pictures\""), std::string::npos);
  ExpectNoNetworkReferences(html_);
}

TEST_F(EvalReport, FolderWithoutPicturesSaysSo) {
  const fs::path dir = TempDir("eval-no-pictures");
  fs::copy_file(dir_ / "pairs.jsonl", dir / "pairs.jsonl");
  fs::copy_file(dir_ / "summary.json", dir / "summary.json");
  fs::copy_file(dir_ / "summary.md", dir / "summary.md");
  const std::string html = BuildReportHtml(dir.string());
  EXPECT_NE(html.find("id=\"no-pictures\""), std::string::npos);
  EXPECT_EQ(DataImages(html), 0);
  EXPECT_EQ(CountOccurrences(TableBody(html, "pairs"), "<tr>"), 3);
  fs::remove_all(dir);
}

TEST_F(EvalReport, ChromiumLoadsTablesImagesAndSortsByError) {
  if (!fs::exists(kChromium))
    GTEST_SKIP() << kChromium << " is absent (scripts/setup.sh installs it)";
  const fs::path profile = TempDir("chromium-eval");
  const std::string url = "file://" + (dir_ / "report.html").string();
  const std::string dom = DumpDom(url, profile);
  ASSERT_NE(dom.find("</html>"), std::string::npos) << "Chromium printed no page:\n" << dom;
  EXPECT_EQ(CountOccurrences(TableBody(dom, "pairs"), "<tr>"), 3);
  EXPECT_GE(CountOccurrences(dom, "<table class=\"summary\">"), 1);
  EXPECT_EQ(DataImages(dom), 2);
  // Sorted by the page's script: rotation errors 2.5, 40, 0.7 -> ascending 2, 0, 1.
  const std::string sorted = DumpDom(url + "#sort=rotation_error", profile);
  EXPECT_EQ(RowOrder(TableBody(sorted, "pairs")), (std::vector<int>{2, 0, 1}));
  const std::string reversed = DumpDom(url + "#sort=rotation_error:desc", profile);
  EXPECT_EQ(RowOrder(TableBody(reversed, "pairs")), (std::vector<int>{1, 0, 2}));
  EXPECT_NE(reversed.find("aria-sort=\"descending\""), std::string::npos);
  fs::remove_all(profile);
}

TEST(EvalReportMatch, ThreeDMatchFolderShowsRegisteredAndRecallError) {
  const fs::path dir = TempDir("eval-3dmatch");
  RunInfo info;
  info.protocol = "3dmatch";
  info.method = "fpfh";
  std::vector<PairRecord> records;
  for (int k = 0; k < 2; ++k) {
    PairTask task;
    task.benchmark = "3DMatch";
    task.scene = "7-scenes-redkitchen";
    task.target_id = 0;
    task.source_id = 5 + k;
    task.log_n = 20;
    info.tasks.push_back(task);
    PairRecord r;
    r.key = task.Key();
    r.benchmark = task.benchmark;
    r.scene = task.scene;
    r.method = info.method;
    r.target_id = task.target_id;
    r.source_id = task.source_id;
    r.log_n = task.log_n;
    r.recall_error = k == 0 ? 0.01 : 0.5;
    r.registered = k == 0;
    r.valid = true;
    records.push_back(r);
  }
  records[1].error = "frame-000300.depth.png: not found";
  WritePairsJsonl((dir / "pairs.jsonl").string(), records);
  WriteSummary(dir.string(), info, info.tasks, records);
  const std::string html = BuildReportHtml(dir.string());
  EXPECT_NE(html.find("registered (E &lt;= 0.04)"), std::string::npos);
  EXPECT_NE(html.find("RR (%)"), std::string::npos);  // the summary.md table
  const std::string body = TableBody(html, "pairs");
  EXPECT_EQ(CountOccurrences(body, "<tr>"), 2);
  EXPECT_NE(body.find("data-value=\"yes\""), std::string::npos);
  EXPECT_NE(body.find("data-value=\"0.01\""), std::string::npos);
  // The pair that could not be run says why.
  EXPECT_NE(body.find("data-value=\"error\""), std::string::npos);
  EXPECT_NE(body.find("frame-000300.depth.png: not found"), std::string::npos);
  EXPECT_EQ(body.find("data-value=\"0.5\""), std::string::npos);  // no E for it
  ExpectNoNetworkReferences(html);
  fs::remove_all(dir);
}

// ---- what the page reads and where it is written ---------------------------------------------

// One pair of benchmark `benchmark` / scene "s" (target 0, source 20) in a new eval folder.
fs::path OnePairEvalFolder(const std::string& what, const std::string& benchmark) {
  const fs::path dir = TempDir(what);
  PairRecord r;
  r.benchmark = benchmark;
  r.scene = "s";
  r.key = benchmark + "/s 0 20";
  r.method = "zeroreg";
  r.source_id = 20;
  r.valid = true;
  r.reason = "ok";
  WritePairsJsonl((dir / "pairs.jsonl").string(), {r});
  return dir;
}

void WritePicture(const fs::path& path) {
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), cv::Mat(30, 50, CV_8UC3, cv::Scalar(40, 90, 200))));
}

// A heading line that is only '#' (or '#' and spaces) is an empty heading, not a crash.
TEST(ReportInputs, HashAloneInSummaryMdIsAnEmptyHeading) {
  const fs::path dir = OnePairEvalFolder("hash-alone", "b");
  std::ofstream(dir / "summary.md") << "# Results\n#\n##   \n| a | b |\n|---|---|\n| 1 | 2 |\n";
  std::string html;
  ASSERT_NO_THROW(html = BuildReportHtml(dir.string()));
  EXPECT_NE(html.find("<h3>Results</h3>"), std::string::npos);
  EXPECT_NE(html.find("<table class=\"summary\">"), std::string::npos);
  const auto r = testing::RunCli("report '" + dir.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  fs::remove_all(dir);
}

// `benchmark` of pairs.jsonl names the picture folder: one that climbs out of the results folder
// (a shared report would carry the viewer's files) embeds nothing.
TEST(ReportInputs, PicturesOutsideTheFolderAreNotEmbedded) {
  const fs::path outside = TempDir("outside");
  WritePicture(outside / "s" / "0_20" / "registered-view0.png");
  const std::string climb = "../../" + outside.filename().string();
  const fs::path dir = OnePairEvalFolder("climbing", climb);
  fs::create_directories(dir / "pictures");  // for the system to resolve pictures/../..
  ASSERT_TRUE(fs::exists(dir / PairPictureFolder(climb, "s", 0, 20) / "registered-view0.png"));
  const std::string html = BuildReportHtml(dir.string());
  EXPECT_EQ(DataImages(html), 0);
  fs::remove_all(dir);
  fs::remove_all(outside);
}

// Links in pictures/ (to a file or a folder elsewhere) are not followed; regular files are shown.
TEST(ReportInputs, LinksInPicturesAreNotFollowed) {
  const fs::path outside = TempDir("outside-links");
  WritePicture(outside / "secret.png");
  WritePicture(outside / "folder" / "registered-view0.png");
  const fs::path dir = OnePairEvalFolder("links", "b");
  const fs::path pair = dir / PairPictureFolder("b", "s", 0, 20);
  WritePicture(pair / "correspondences-view0.png");
  fs::create_symlink(outside / "secret.png", pair / "registered-view0.png");
  EXPECT_EQ(DataImages(BuildReportHtml(dir.string())), 1);  // the regular file only

  // The pair's folder itself a link to a folder elsewhere.
  fs::remove_all(dir / "pictures");
  fs::create_directories(dir / "pictures" / "b" / "s");
  fs::create_directory_symlink(outside / "folder", pair);
  EXPECT_EQ(DataImages(BuildReportHtml(dir.string())), 0);

  // A register folder's pictures/ a link.
  const fs::path reg = TempDir("links-register");
  std::ofstream(reg / "result.json") << R"({"result": {"valid": true}})";
  fs::create_directory_symlink(outside / "folder", reg / "pictures");
  EXPECT_EQ(DataImages(BuildReportHtml(reg.string())), 0);
  // summary.md a link to a file elsewhere: its text is not shown.
  std::ofstream(outside / "private.txt") << "PRIVATE-TEXT\n";
  fs::create_symlink(outside / "private.txt", dir / "summary.md");
  std::string html;
  try {
    html = BuildReportHtml(dir.string());
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("summary.md"), std::string::npos) << e.what();
  }
  EXPECT_EQ(html.find("PRIVATE-TEXT"), std::string::npos);
  fs::remove_all(dir);
  fs::remove_all(reg);
  fs::remove_all(outside);
}

// The page goes through a temporary file: a failed write leaves the previous page whole and says
// why (here the file-size limit stands for a full disk).
TEST(ReportOutput, FailedWriteKeepsThePreviousPageAndSaysWhy) {
  const fs::path dir = OnePairEvalFolder("failed-write", "b");
  const std::string out = (dir / "report.html").string();
  WriteReport(dir.string(), out);
  const std::string previous = ReadText(out);
  ASSERT_GT(previous.size(), 4000u);
  std::string message;
  {
    struct sigaction ignore {
    }, old{};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &old);
    rlimit limit{}, saved{};
    ::getrlimit(RLIMIT_FSIZE, &saved);
    limit = saved;
    limit.rlim_cur = 2000;
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      WriteReport(dir.string(), out);
    } catch (const InputError& e) {
      message = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &saved);
    ::sigaction(SIGXFSZ, &old, nullptr);
  }
  EXPECT_NE(message.find(out), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_TRUE(ReadText(out) == previous) << "the previous page was damaged";
  // A full device: the reason is the system's.
  if (fs::is_character_file("/dev/full")) {
    fs::create_symlink("/dev/full", dir / "full");  // a link: a regression replaces only it
    try {
      WriteReport(dir.string(), (dir / "full").string());
      ADD_FAILURE() << "no error writing to /dev/full";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos)
          << e.what();
    }
  }
  fs::remove_all(dir);
}

// --out naming a file of the results (pairs.jsonl, summary.json, ...) is refused; an earlier page
// is replaced.
TEST(ReportOutput, OutNamingAResultsFileIsRefused) {
  const fs::path dir = OnePairEvalFolder("out-over-results", "b");
  std::ofstream(dir / "summary.json") << "{}\n";
  const std::string records = ReadText(dir / "pairs.jsonl");
  for (const char* name : {"pairs.jsonl", "summary.json"}) {
    const std::string out = (dir / name).string();
    const std::string before = ReadText(out);
    const auto r = testing::RunCli("report '" + dir.string() + "' --out '" + out + "'");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(out), std::string::npos) << r.output;
    EXPECT_TRUE(ReadText(out) == before) << name << " was overwritten";
  }
  EXPECT_EQ(ReadText(dir / "pairs.jsonl"), records);
  const std::string page = (dir / "page.html").string();
  EXPECT_EQ(testing::RunCli("report '" + dir.string() + "' --out '" + page + "'").exit_code, 0);
  const auto again = testing::RunCli("report '" + dir.string() + "' --out '" + page + "'");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  // --out /dev/stdout, through a link to it (a regression would replace the link, not the
  // machine's /dev/stdout): the page comes out on stdout and the link stays.
  fs::create_symlink("/dev/stdout", dir / "stdout");
  const auto piped =
      testing::RunCli("report '" + dir.string() + "' --out '" + (dir / "stdout").string() + "'");
  EXPECT_EQ(piped.exit_code, 0) << piped.output;
  EXPECT_EQ(piped.output.rfind("<!DOCTYPE html>", 0), 0u) << piped.output.substr(0, 200);
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "stdout")));
  fs::remove_all(dir);
}

// ---- a real register --out-dir run -------------------------------------------------------------

// Redkitchen frame 20 registered onto frame 0 with SIFT (no model files needed), once for the
// suite, written with both --out and --out-dir.
class RegisterReport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = TempDir("register");
    const std::string data = testing::RedkitchenDir();
    run_ = testing::RunCli("register --source '" + data + "@20' --target '" + data +
                           "@0' --features sift --out '" + (dir_ / "out.json").string() +
                           "' --out-dir '" + (dir_ / "run").string() + "'");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void SetUp() override { ASSERT_EQ(run_.exit_code, 0) << run_.output; }

  static fs::path dir_;
  static testing::CommandResult run_;
};
fs::path RegisterReport::dir_;
testing::CommandResult RegisterReport::run_;

TEST_F(RegisterReport, OutDirHoldsResultPicturesAndPly) {
  const fs::path run = dir_ / "run";
  // result.json is the --out JSON.
  EXPECT_EQ(ReadText(run / "result.json"), ReadText(dir_ / "out.json"));
  EXPECT_TRUE(fs::exists(run / "pictures" / "correspondences-view0.png"));
  EXPECT_TRUE(fs::exists(run / "pictures" / "registered-view0.png"));

  const nlohmann::json result = nlohmann::json::parse(ReadText(run / "result.json"));
  Transform T;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) T(r, c) = result["result"]["T_target_source"][r][c].get<double>();
  }
  open3d::geometry::PointCloud registered, source, target;
  ASSERT_TRUE(open3d::io::ReadPointCloud((run / "registered.ply").string(), registered));
  ASSERT_TRUE(open3d::io::ReadPointCloud((run / "source.ply").string(), source));
  ASSERT_TRUE(open3d::io::ReadPointCloud((run / "target.ply").string(), target));
  // A 640x480 frame at 1 cm: tens of thousands of points, far fewer than its 307k pixels.
  EXPECT_GT(source.points_.size(), 10000u);
  EXPECT_LT(source.points_.size(), 200000u);
  EXPECT_GT(target.points_.size(), 10000u);
  ASSERT_EQ(registered.points_.size(), target.points_.size() + source.points_.size());
  ASSERT_TRUE(registered.HasColors());
  const size_t nt = target.points_.size();
  double worst_target = 0, worst_source = 0;
  int wrong_colours = 0;
  for (size_t k = 0; k < registered.points_.size(); ++k) {
    const bool is_target = k < nt;
    const Eigen::Vector3d expected_colour = is_target ? kTargetColor : kSourceColor;
    if ((registered.colors_[k] - expected_colour).cwiseAbs().maxCoeff() > 1.0 / 255) {
      ++wrong_colours;
    }
    if (is_target) {
      worst_target = std::max(worst_target, (registered.points_[k] - target.points_[k]).norm());
    } else {
      const Eigen::Vector3d moved = (T * source.points_[k - nt].homogeneous()).head<3>();
      worst_source = std::max(worst_source, (registered.points_[k] - moved).norm());
    }
  }
  EXPECT_EQ(wrong_colours, 0);
  EXPECT_LE(worst_target, 1e-6);
  EXPECT_LE(worst_source, 1e-5);  // float32 storage of points a few metres away
  // source.ply / target.ply are in the scans' own colours, not the origin colours.
  int own = 0;
  for (const auto& c : source.colors_) own += (c - kSourceColor).norm() > 0.05;
  EXPECT_GT(own, static_cast<int>(source.colors_.size() / 2));
}

TEST_F(RegisterReport, PageShowsTheResultAndEveryPicture) {
  const fs::path run = dir_ / "run";
  const std::string out = (dir_ / "register.html").string();
  const auto r = testing::RunCli("report '" + run.string() + "' --out '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = ReadText(out);
  int pictures = 0;
  for (const auto& entry : fs::directory_iterator(run / "pictures")) {
    pictures += entry.path().extension() == ".png";
  }
  ASSERT_GE(pictures, 2);
  EXPECT_EQ(DataImages(html), pictures);
  EXPECT_EQ(CountOccurrences(TableBody(html, "pairs"), "<tr>"), 1);
  EXPECT_NE(html.find("registered.ply"), std::string::npos);
  ExpectNoNetworkReferences(html);
  // Pictures are 1280 px wide or less, so the page stays small.
  EXPECT_LT(html.size(), 5u * 1000 * 1000);

  if (!fs::exists(kChromium))
    GTEST_SKIP() << kChromium << " is absent (scripts/setup.sh installs it)";
  const fs::path profile = TempDir("chromium-register");
  const std::string dom = DumpDom("file://" + out, profile);
  ASSERT_NE(dom.find("</html>"), std::string::npos) << "Chromium printed no page:\n" << dom;
  EXPECT_EQ(CountOccurrences(TableBody(dom, "pairs"), "<tr>"), 1);
  EXPECT_EQ(DataImages(dom), pictures);
  EXPECT_NE(dom.find("class=\"ok\">valid"), std::string::npos);
  fs::remove_all(profile);
}

}  // namespace
}  // namespace zeroreg

namespace zeroreg {
namespace {

// An ambiguous result: the page lists both poses and embeds the picture of both overlays.
TEST(ReportAmbiguous, ListsEveryPoseThatFitsAndShowsBothOverlays) {
  const fs::path reg = TempDir("ambiguous-register");
  std::ofstream(reg / "result.json") << R"({"result": {"valid": false, "ambiguous": true,
      "alternatives": [
        {"name": "image-fallback", "score": 0.571, "overlap": 0.5, "violation": 0.02,
         "apart_m": 0.0, "outside_prior": false},
        {"name": "turned-180 icp", "score": 0.31, "overlap": 0.36, "violation": 0.16,
         "apart_m": 0.93, "outside_prior": false}]}})";
  fs::create_directories(reg / "pictures");
  cv::imwrite((reg / "pictures" / "ambiguous-view0.png").string(),
              cv::Mat(40, 80, CV_8UC3, cv::Scalar(40, 110, 200)));
  const std::string html = BuildReportHtml(reg.string());
  EXPECT_NE(html.find("Ambiguous: these poses fit the scans"), std::string::npos);
  EXPECT_NE(html.find("turned-180 icp"), std::string::npos);
  EXPECT_NE(html.find("0.930"), std::string::npos);
  EXPECT_NE(html.find("two poses fit these scans"), std::string::npos);  // the picture's caption
  EXPECT_EQ(DataImages(html), 1);
  fs::remove_all(reg);
}

}  // namespace
}  // namespace zeroreg
