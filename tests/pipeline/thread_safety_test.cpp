// One Pipeline shared by several threads gives, for every call, exactly the result of a
// single-threaded call (YOLOX, Darknet and XFeat run one cv::dnn::Net per model, under a lock).
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "test_paths.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

Scan Frame(int id) { return LoadScan(testing::RedkitchenDir() + "@" + std::to_string(id)); }

// Registers 20 -> 0 `per_thread` times on each of `threads` threads sharing `pipeline`, and
// checks every result against the single-threaded one.
void ExpectSameAsSingleThreaded(const Pipeline& pipeline, int threads, int per_thread) {
  const Scan source = Frame(20), target = Frame(0);
  const RegistrationResult reference = pipeline.Register(source, target);
  std::vector<std::vector<RegistrationResult>> results(static_cast<size_t>(threads));
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int k = 0; k < per_thread; ++k) {
        results[static_cast<size_t>(t)].push_back(pipeline.Register(source, target));
      }
    });
  }
  for (std::thread& w : workers) w.join();
  for (const auto& per : results) {
    for (const RegistrationResult& r : per) {
      EXPECT_EQ(r.T_target_source, reference.T_target_source);
      EXPECT_EQ(r.valid, reference.valid);
      EXPECT_EQ(r.source_objects.size(), reference.source_objects.size());
      EXPECT_EQ(r.target_objects.size(), reference.target_objects.size());
      EXPECT_EQ(r.num_correspondences, reference.num_correspondences);
      EXPECT_EQ(r.num_inliers, reference.num_inliers);
    }
  }
}

TEST(PipelineThreads, SharedYoloxXfeatPipelineGivesSingleThreadedResults) {
  const Pipeline pipeline{PipelineConfig()};
  ExpectSameAsSingleThreaded(pipeline, 3, 2);
}

TEST(PipelineThreads, SharedDarknetPipelineGivesSingleThreadedResults) {
  PipelineConfig config;
  config.detector.backend = "darknet";
  config.features.backend = "sift";  // the detector is what is under test here
  const Pipeline pipeline(config);
  ExpectSameAsSingleThreaded(pipeline, 3, 2);
}

}  // namespace
}  // namespace zeroreg
