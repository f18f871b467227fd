// inference.graph_cache: ONNX Runtime's optimised graph of a model, saved by one
// process and loaded by the next, must give bit-identical outputs; entries are keyed to the
// model's bytes; a damaged or unwritable cache never changes a result or raises an error.
#include "inference/graph_cache.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "assets/assets_internal.hpp"
#include "assets/sha256.hpp"
#include "detect/backends.hpp"
#include "detect/perception_test_util.hpp"
#include "features/xfeat_extractor.hpp"
#include "inference/onnx_model.hpp"
#include "zeroreg/assets.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using perception_test::AssetsDir;
using perception_test::FramePath;
using perception_test::ModelPaths;
using perception_test::TempDir;

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Sets an environment variable for one scope and restores it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    had_ = std::getenv(name) != nullptr;
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_.c_str(), old_.c_str(), 1);
    } else {
      unsetenv(name_.c_str());
    }
  }

 private:
  std::string name_, old_;
  bool had_ = false;
};

TEST(GraphCache, DirectoryFollowsTheSettingAndTheEnvironment) {
  EXPECT_FALSE(GraphCacheDirectory("off").has_value());
  EXPECT_EQ(GraphCacheDirectory("/some/dir").value(), "/some/dir");
  {
    ScopedEnv cache("ZEROREG_CACHE_DIR", "/a/cache");
    EXPECT_EQ(GraphCacheDirectory("auto").value(), "/a/cache/onnxruntime-graphs");
  }
  {
    ScopedEnv cache("ZEROREG_CACHE_DIR", nullptr), xdg("XDG_CACHE_HOME", "/xdg");
    EXPECT_EQ(GraphCacheDirectory("auto").value(), "/xdg/zeroreg/onnxruntime-graphs");
  }
  {
    ScopedEnv cache("ZEROREG_CACHE_DIR", nullptr), xdg("XDG_CACHE_HOME", nullptr),
        home("HOME", "/home/u");
    EXPECT_EQ(GraphCacheDirectory("auto").value(), "/home/u/.cache/zeroreg/onnxruntime-graphs");
  }
  {
    ScopedEnv cache("ZEROREG_CACHE_DIR", nullptr), xdg("XDG_CACHE_HOME", nullptr),
        home("HOME", nullptr);
    EXPECT_FALSE(GraphCacheDirectory("auto").has_value());
  }
}

TEST(GraphCache, EntryIsKeyedToTheModelBytesNotItsPath) {
  TempDir dir("graph_key");
  fs::create_directories(dir.str() + "/a");
  fs::create_directories(dir.str() + "/b");
  WriteFile(dir.str() + "/a/model.onnx", "bytes one");
  WriteFile(dir.str() + "/b/model.onnx", "bytes one");
  WriteFile(dir.str() + "/b/other.onnx", "bytes two");
  const std::string cache = dir.str() + "/cache";
  const GraphCacheEntry a = GraphCacheEntryFor(cache, dir.str() + "/a/model.onnx", "1.2.3");
  const GraphCacheEntry b = GraphCacheEntryFor(cache, dir.str() + "/b/model.onnx", "1.2.3");
  EXPECT_EQ(a.graph_path, b.graph_path);
  EXPECT_EQ(fs::path(a.graph_path).parent_path(), fs::path(cache));
  EXPECT_EQ(fs::path(a.graph_path).filename().string().rfind("model-", 0), 0u);
  WriteFile(dir.str() + "/b/model.onnx", "bytes two");  // same name, other bytes
  EXPECT_NE(GraphCacheEntryFor(cache, dir.str() + "/b/model.onnx", "1.2.3").graph_path,
            a.graph_path);
  EXPECT_NE(GraphCacheEntryFor(cache, dir.str() + "/a/model.onnx", "1.2.4").graph_path,
            a.graph_path);
  EXPECT_EQ(a.digest_path, a.graph_path + ".hmac");
  EXPECT_FALSE(CpuSignature().empty());
  EXPECT_EQ(CpuSignature(), CpuSignature());
}

// The model's digest is remembered for the process (detail::Sha256OfFileRemembered): RequireAsset
// hashed it already, so keying its graph-cache entry does not read the model again.
TEST(GraphCache, EntryKeyReusesTheDigestTheModelWasVerifiedWith) {
  TempDir dir("graph_key_once");
  const std::string model = dir.str() + "/model.onnx";
  WriteFile(model, "settled bytes");
  fs::last_write_time(model, fs::last_write_time(model) - std::chrono::hours(1));
  const std::size_t before = detail::AssetFilesHashedForTesting();
  EXPECT_EQ(detail::Sha256OfFileRemembered(model), Sha256OfFile(model));
  const GraphCacheEntry first = GraphCacheEntryFor(dir.str() + "/cache", model, "1.2.3");
  const GraphCacheEntry second = GraphCacheEntryFor(dir.str() + "/cache", model, "1.2.3");
  EXPECT_EQ(first.graph_path, second.graph_path);
  EXPECT_EQ(detail::AssetFilesHashedForTesting(), before + 1);
}

TEST(GraphCache, CommittedEntryIsValidUntilDamaged) {
  TempDir dir("graph_commit");
  WriteFile(dir.str() + "/model.onnx", "model");
  const GraphCacheEntry entry =
      GraphCacheEntryFor(dir.str() + "/new/sub", dir.str() + "/model.onnx", "1");
  EXPECT_FALSE(GraphCacheEntryValid(entry));
  const std::optional<std::string> scratch = GraphCacheScratchPath(entry);
  ASSERT_TRUE(scratch.has_value());  // the directories were created
  EXPECT_NE(*scratch, GraphCacheScratchPath(entry).value());
  WriteFile(*scratch, "optimised graph");
  ASSERT_TRUE(CommitGraphCacheEntry(entry, *scratch));
  EXPECT_FALSE(fs::exists(*scratch));
  EXPECT_TRUE(GraphCacheEntryValid(entry));
  WriteFile(entry.graph_path, "optimised graph, changed");
  EXPECT_FALSE(GraphCacheEntryValid(entry));
  WriteFile(entry.graph_path, "optimised graph");
  EXPECT_TRUE(GraphCacheEntryValid(entry));
  fs::remove(entry.digest_path);
  EXPECT_FALSE(GraphCacheEntryValid(entry));
  // Nothing written by the runtime: no entry, no leftovers.
  EXPECT_FALSE(CommitGraphCacheEntry(entry, *scratch));
}

// The digest beside a graph is not enough: a graph altered by someone else, with its sha256
// recomputed, or another model's graph copied under this entry's name, is never loaded.
TEST(GraphCache, TamperedGraphWithARecomputedDigestIsNotLoaded) {
  TempDir dir("graph_tampered");
  WriteFile(dir.str() + "/model.onnx", "model");
  WriteFile(dir.str() + "/other.onnx", "another model");
  const std::string cache = dir.str() + "/cache";
  const GraphCacheEntry entry = GraphCacheEntryFor(cache, dir.str() + "/model.onnx", "1");
  const std::optional<std::string> scratch = GraphCacheScratchPath(entry);
  ASSERT_TRUE(scratch.has_value());
  WriteFile(*scratch, "optimised graph");
  ASSERT_TRUE(CommitGraphCacheEntry(entry, *scratch));
  ASSERT_TRUE(GraphCacheEntryValid(entry));

  WriteFile(entry.graph_path, "optimised graph with altered weights");
  WriteFile(entry.digest_path, detail::Sha256Hex("optimised graph with altered weights") + "\n");
  EXPECT_FALSE(GraphCacheEntryValid(entry));
  EXPECT_FALSE(ReadValidGraph(entry).has_value());

  // Another model's graph and check line, copied under this entry's name.
  const GraphCacheEntry other = GraphCacheEntryFor(cache, dir.str() + "/other.onnx", "1");
  const std::optional<std::string> other_scratch = GraphCacheScratchPath(other);
  ASSERT_TRUE(other_scratch.has_value());
  WriteFile(*other_scratch, "other graph");
  ASSERT_TRUE(CommitGraphCacheEntry(other, *other_scratch));
  ASSERT_TRUE(GraphCacheEntryValid(other));
  fs::copy_file(other.graph_path, entry.graph_path, fs::copy_options::overwrite_existing);
  fs::copy_file(other.digest_path, entry.digest_path, fs::copy_options::overwrite_existing);
  EXPECT_FALSE(GraphCacheEntryValid(entry));
}

TEST(GraphCache, UnwritableDirectoryGivesNoScratchPath) {
  TempDir dir("graph_unwritable");
  WriteFile(dir.str() + "/model.onnx", "model");
  WriteFile(dir.str() + "/a-file", "not a directory");
  const GraphCacheEntry entry =
      GraphCacheEntryFor(dir.str() + "/a-file/cache", dir.str() + "/model.onnx", "1");
  EXPECT_FALSE(GraphCacheScratchPath(entry).has_value());
  EXPECT_FALSE(GraphCacheEntryValid(entry));
}

InferenceConfig OnnxRuntime(const std::string& graph_cache) {
  InferenceConfig c;
  c.engine = "onnxruntime";
  c.graph_cache = graph_cache;
  return c;
}

void ExpectSameFeatures(const ImageFeatures& a, const ImageFeatures& b, int frame) {
  ASSERT_EQ(a.keypoints.size(), b.keypoints.size()) << "frame " << frame;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    ASSERT_EQ(a.keypoints[i], b.keypoints[i]) << "frame " << frame << " keypoint " << i;
    ASSERT_EQ(a.scores[i], b.scores[i]) << "frame " << frame << " keypoint " << i;
  }
  EXPECT_TRUE(a.descriptors == b.descriptors) << "frame " << frame;
}

// The first session optimises and saves, the second loads the saved graph; XFeat's keypoints,
// scores and descriptors and YOLOX's and PicoDet's boxes are bit-identical to a session without
// the cache (SAM: tests/segment/sam_segmenter_test.cpp).
TEST(GraphCache, CachedGraphsGiveBitIdenticalOutputs) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  TempDir cache("graph_cache");
  const std::string xfeat = AssetsDir() + "/xfeat/xfeat_any_size.onnx";
  const auto cold = LoadOnnxModel(xfeat, "XFeat", InferenceEngine::kOnnxRuntime, 1, cache.str());
  EXPECT_FALSE(cold->FromGraphCache());
  const auto warm = LoadOnnxModel(xfeat, "XFeat", InferenceEngine::kOnnxRuntime, 1, cache.str());
  EXPECT_TRUE(warm->FromGraphCache());
  EXPECT_EQ(warm->OutputNames(), cold->OutputNames());

  const FeatureConfig features;
  const XFeatExtractor plain(xfeat, features, OnnxRuntime("off"));
  const XFeatExtractor cached(xfeat, features, OnnxRuntime(cache.str()));
  const DetectorModelPaths paths = ModelPaths();
  YoloxDetector det_plain(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{},
                          OnnxRuntime("off"));
  YoloxDetector det_cold(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{},
                         OnnxRuntime(cache.str()));
  YoloxDetector det_warm(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{},
                         OnnxRuntime(cache.str()));
  const auto picodet = [&](const std::string& graph_cache) {
    return std::make_unique<PicodetDetector>(paths.picodet_onnx, paths.picodet_opencv_onnx,
                                             paths.picodet_classes, DetectorConfig{},
                                             OnnxRuntime(graph_cache));
  };
  const auto pico_plain = picodet("off"), pico_cold = picodet(cache.str()),
             pico_warm = picodet(cache.str());
  for (int frame : {0, 500, 802}) {
    const cv::Mat img = cv::imread(FramePath(frame, "color.jpg"), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    ExpectSameFeatures(plain.Extract(img), cached.Extract(img), frame);
    const auto expect_same = [&](Detector& reference,
                                 std::initializer_list<Detector*> cached_ones) {
      const std::vector<Detection> a = reference.Detect(img, "a.jpg");
      for (Detector* d : cached_ones) {
        const std::vector<Detection> b = d->Detect(img, "b.jpg");
        ASSERT_EQ(a.size(), b.size()) << "frame " << frame;
        for (size_t i = 0; i < a.size(); ++i) {
          EXPECT_EQ(a[i].box, b[i].box) << "frame " << frame;
          EXPECT_EQ(a[i].score, b[i].score) << "frame " << frame;
          EXPECT_EQ(a[i].label, b[i].label) << "frame " << frame;
        }
      }
    };
    expect_same(det_plain, {&det_cold, &det_warm});
    expect_same(*pico_plain, {pico_cold.get(), pico_warm.get()});
  }
}

// A damaged graph is not loaded: the model is optimised again, the entry rewritten, and the next
// session uses it. A cache that cannot be written changes nothing but the time.
TEST(GraphCache, DamagedOrUnwritableCacheFallsBackToTheModel) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  TempDir cache("graph_damaged");
  const std::string yolox = ModelPaths().yolox_onnx;
  const auto load = [&](const std::string& dir) {
    return LoadOnnxModel(yolox, "YOLOX", InferenceEngine::kOnnxRuntime, 1, dir);
  };
  EXPECT_FALSE(load(cache.str())->FromGraphCache());
  const GraphCacheEntry entry = GraphCacheEntryFor(cache.str(), yolox, OnnxRuntimeVersion());
  ASSERT_TRUE(GraphCacheEntryValid(entry));
  WriteFile(entry.graph_path, "not an ONNX graph");
  EXPECT_FALSE(load(cache.str())->FromGraphCache());
  EXPECT_TRUE(GraphCacheEntryValid(entry));
  EXPECT_TRUE(load(cache.str())->FromGraphCache());
  // A graph whose digest matches but that ONNX Runtime cannot load: optimised anew, replaced.
  const std::optional<std::string> scratch = GraphCacheScratchPath(entry);
  ASSERT_TRUE(scratch.has_value());
  WriteFile(*scratch, "still not an ONNX graph");
  ASSERT_TRUE(CommitGraphCacheEntry(entry, *scratch));
  ASSERT_TRUE(GraphCacheEntryValid(entry));
  EXPECT_FALSE(load(cache.str())->FromGraphCache());
  EXPECT_TRUE(load(cache.str())->FromGraphCache());
  // Nothing but the entries themselves is left in the directory (no scratch files).
  for (const auto& file : fs::directory_iterator(cache.str())) {
    const std::string name = file.path().filename().string();
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
  }

  WriteFile(cache.str() + "/a-file", "x");
  const auto model = load(cache.str() + "/a-file/graphs");
  EXPECT_FALSE(model->FromGraphCache());
  EXPECT_FALSE(model->OutputNames().empty());
  EXPECT_FALSE(load("off")->FromGraphCache());
}

}  // namespace
}  // namespace zeroreg
