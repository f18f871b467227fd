// The prepared-scan cache of `zeroreg eval`: each key prepared once while it is held, least
// recently used out first by count and by memory, failures not cached, concurrent askers of one
// key served by one preparation.
#include "eval/prepared_cache.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "eval/methods.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

// Real prepared scans are what the cache holds; SIFT on the whole-image path needs no model and
// is quick.
class PreparedCacheTest : public ::testing::Test {
 protected:
  static PipelineConfig Config() {
    PipelineConfig c;
    c.features.backend = "sift";
    c.method.object_level = false;
    return c;
  }
  PreparedCacheTest() : pipeline_(Config()) {}
  std::function<PreparedScan()> Preparer(int frame) {
    return [this, frame] {
      ++prepared_;
      return pipeline_.Prepare(LoadScan(testing::RedkitchenDir() + "@" + std::to_string(frame)));
    };
  }
  Pipeline pipeline_;
  std::atomic<int> prepared_{0};
};

TEST_F(PreparedCacheTest, EachKeyIsPreparedOnceWhileHeldAndTheOldestGoesFirst) {
  PreparedScanCache cache(/*max_scans=*/2, /*max_bytes=*/std::size_t{1} << 40);
  const PreparedScan a = cache.Get("a", Preparer(0));
  EXPECT_EQ(cache.Get("a", Preparer(0)).MemoryBytes(), a.MemoryBytes());
  EXPECT_EQ(prepared_, 1);
  cache.Get("b", Preparer(10));
  cache.Get("a", Preparer(0));   // a is now the most recently used
  cache.Get("c", Preparer(20));  // evicts b
  EXPECT_EQ(prepared_, 3);
  cache.Get("a", Preparer(0));
  EXPECT_EQ(prepared_, 3);
  cache.Get("b", Preparer(10));  // prepared again
  EXPECT_EQ(prepared_, 4);
  const PreparedScanCache::Stats s = cache.stats();
  EXPECT_EQ(s.scans, 2u);
  EXPECT_EQ(s.misses, 4u);
  EXPECT_EQ(s.hits, 3u);
  EXPECT_EQ(s.evictions, 2u);
}

TEST_F(PreparedCacheTest, MemoryBoundKeepsOnlyWhatFits) {
  const std::size_t one = Preparer(0)().MemoryBytes();
  prepared_ = 0;
  ASSERT_GT(one, std::size_t{1} << 20);  // a 640x480 RGB-D frame with features: > 1 MiB
  PreparedScanCache cache(/*max_scans=*/100, /*max_bytes=*/one * 3 / 2);
  cache.Get("a", Preparer(0));
  cache.Get("b", Preparer(10));  // both do not fit: a goes
  EXPECT_EQ(cache.stats().scans, 1u);
  EXPECT_LE(cache.stats().bytes, one * 3 / 2);
  cache.Get("b", Preparer(10));
  EXPECT_EQ(prepared_, 2);
  // One scan larger than the whole budget is still returned (and is all that is held).
  PreparedScanCache tiny(100, 1);
  EXPECT_FALSE(tiny.Get("a", Preparer(0)).empty());
  EXPECT_EQ(tiny.stats().scans, 1u);
}

// A prepared scan grows when it is first the source of a pair that needs its turned images'
// features (redkitchen frames 636 and 849 share no surface, so every source runs, the turned images
// last); the budget counts what it holds at the next insertion.
TEST_F(PreparedCacheTest, AScanThatGrowsAfterItIsCachedIsCountedAsItIsNow) {
  PreparedScanCache cache(/*max_scans=*/100, /*max_bytes=*/std::size_t{1} << 40);
  const PreparedScan source = cache.Get("source", Preparer(636));
  const PreparedScan target = cache.Get("target", Preparer(849));
  const std::size_t before = source.MemoryBytes();
  const RegistrationResult r = pipeline_.Register(source, target);
  ASSERT_TRUE(std::any_of(r.timings.begin(), r.timings.end(), [](const StageTime& t) {
    return t.stage == "hypothesis turned images";
  })) << r.reason;
  EXPECT_GT(source.MemoryBytes(), before);
  const PreparedScan other = cache.Get("other", Preparer(20));  // an insertion: sizes re-read
  EXPECT_EQ(cache.stats().bytes, source.MemoryBytes() + target.MemoryBytes() + other.MemoryBytes());
}

TEST_F(PreparedCacheTest, FailuresAreNotCachedAndConcurrentAskersShareOnePreparation) {
  PreparedScanCache cache;
  EXPECT_THROW(cache.Get("bad", []() -> PreparedScan { throw std::runtime_error("no"); }),
               std::runtime_error);
  EXPECT_EQ(cache.stats().scans, 0u);
  std::vector<std::thread> threads;
  std::vector<PreparedScan> got(4);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] { got[t] = cache.Get("a", Preparer(0)); });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(prepared_, 1);
  for (const PreparedScan& p : got) EXPECT_EQ(&p.scan(), &got[0].scan());  // one shared scan
}

TEST(ZeroregMethodWithPreparedScans, SequenceGivesTheRecordsOfPairsRegisteredOneByOne) {
  // A sequence 0 <- 20 <- 40: frame 20 is the source of one pair and the target of the next, and
  // is read and prepared once; every transform is that of registering the pair on its own.
  const MethodFactory cached = MakeMethodFactory("zeroreg", PipelineConfig(), FpfhConfig());
  const std::unique_ptr<PairMethod> method = cached();
  std::map<std::string, int> reads;
  const PairMethod::ScanLoadFunction load = [&](const std::string& ref) {
    ++reads[ref];
    return LoadScan(ref);
  };
  const Pipeline reference{PipelineConfig()};
  const std::string dir = testing::RedkitchenDir() + "@";
  for (int i : {0, 20}) {
    const std::string target = dir + std::to_string(i), source = dir + std::to_string(i + 20);
    const MethodOutput out = method->RunRefs(source, target, load, std::nullopt);
    const RegistrationResult alone = reference.Register(LoadScan(source), LoadScan(target));
    EXPECT_TRUE(alone.valid) << alone.reason;
    EXPECT_EQ(out.T_target_source, alone.T_target_source) << source << " -> " << target;
    EXPECT_EQ(out.valid, alone.valid);
    EXPECT_EQ(out.num_inliers, alone.num_inliers);
  }
  EXPECT_EQ(reads[dir + "20"], 1);  // read once, used twice
  EXPECT_EQ(reads.size(), 3u);
}

}  // namespace
}  // namespace zeroreg
