// Pipeline::Prepare + Register(prepared, prepared) gives the result of Register(scan,
// scan) bit for bit, on real frames, whatever the number of threads and however often a prepared
// scan is reused; and a prepared scan is refused by another Pipeline.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

Scan Frame(const std::string& dataset, int id) {
  return LoadScan(testing::SharedDir() + "/data/" + dataset + "@" + std::to_string(id));
}

// Everything a registration reports except its timings, compared exactly (no tolerance: the
// same arithmetic in the same order must give the same bits).
void ExpectIdentical(const RegistrationResult& a, const RegistrationResult& b) {
  EXPECT_EQ(a.T_target_source, b.T_target_source);
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(PathName(a.path), PathName(b.path));
  EXPECT_EQ(a.num_keypoints_source, b.num_keypoints_source);
  EXPECT_EQ(a.num_keypoints_target, b.num_keypoints_target);
  EXPECT_EQ(a.num_correspondences, b.num_correspondences);
  EXPECT_EQ(a.num_inliers, b.num_inliers);
  EXPECT_EQ(a.inlier_rmse, b.inlier_rmse);
  EXPECT_EQ(a.ransac_iterations, b.ransac_iterations);
  ASSERT_EQ(a.correspondences.size(), b.correspondences.size());
  for (size_t i = 0; i < a.correspondences.size(); ++i) {
    EXPECT_EQ(a.correspondences[i].source, b.correspondences[i].source);
    EXPECT_EQ(a.correspondences[i].target, b.correspondences[i].target);
    EXPECT_EQ(a.correspondences[i].score, b.correspondences[i].score);
  }
  EXPECT_EQ(a.is_inlier, b.is_inlier);
  EXPECT_EQ(a.verification.score, b.verification.score);
  EXPECT_EQ(a.verification.overlap, b.verification.overlap);
  EXPECT_EQ(a.verification.source_samples, b.verification.source_samples);
  ASSERT_EQ(a.candidates.size(), b.candidates.size());
  for (size_t i = 0; i < a.candidates.size(); ++i) {
    EXPECT_EQ(a.candidates[i].name, b.candidates[i].name);
    EXPECT_EQ(a.candidates[i].T_target_source, b.candidates[i].T_target_source);
    EXPECT_EQ(a.candidates[i].score, b.candidates[i].score);
  }
  ASSERT_EQ(a.source_objects.size(), b.source_objects.size());
  for (size_t i = 0; i < a.source_objects.size(); ++i) {
    EXPECT_EQ(a.source_objects[i].label, b.source_objects[i].label);
    EXPECT_EQ(a.source_objects[i].centroid, b.source_objects[i].centroid);
  }
  EXPECT_EQ(a.target_objects.size(), b.target_objects.size());
  ASSERT_EQ(a.object_matches.size(), b.object_matches.size());
  for (size_t i = 0; i < a.object_matches.size(); ++i) {
    EXPECT_EQ(a.object_matches[i].source, b.object_matches[i].source);
    EXPECT_EQ(a.object_matches[i].target, b.object_matches[i].target);
    EXPECT_EQ(a.object_matches[i].num_correspondences, b.object_matches[i].num_correspondences);
  }
}

bool HasStage(const RegistrationResult& r, const std::string& stage) {
  for (const StageTime& t : r.timings) {
    if (t.stage == stage) return true;
  }
  return false;
}

struct RealPair {
  std::string dataset;
  int source, target;
};

// Redkitchen 20 -> 0 takes the object path and ICP; 60 -> 0 is a wider baseline; the HoloLens
// pair has depth with large holes. Each result is also checked to be a correct registration, so
// that an identity of two broken results cannot pass.
class PreparedScanTest : public ::testing::TestWithParam<RealPair> {};

TEST_P(PreparedScanTest, RegisterOfPreparedScansIsBitIdenticalToRegisterOfScans) {
  const RealPair p = GetParam();
  const Scan source = Frame(p.dataset, p.source), target = Frame(p.dataset, p.target);
  const Pipeline pipeline{PipelineConfig()};
  const RegistrationResult direct = pipeline.Register(source, target);
  ASSERT_TRUE(direct.valid) << direct.reason;
  ASSERT_TRUE(direct.count_test_passed);

  const PreparedScan s = pipeline.Prepare(source), t = pipeline.Prepare(target);
  const RegistrationResult prepared = pipeline.Register(s, t);
  ExpectIdentical(direct, prepared);
  // The per-scan stages were done by Prepare: the prepared registration does only the pair's.
  EXPECT_TRUE(HasStage(direct, "features") && HasStage(direct, "geometry"));
  EXPECT_FALSE(HasStage(prepared, "features") || HasStage(prepared, "detect") ||
               HasStage(prepared, "geometry"));
  EXPECT_TRUE(HasStage(prepared, "estimate"));
  EXPECT_GT(s.MemoryBytes(), 0u);
  EXPECT_TRUE(HasStage(direct, "total"));

  // Reused: the same prepared scans again, and in the other roles, from two threads at once.
  const RegistrationResult reverse = pipeline.Register(target, source);
  RegistrationResult again, reverse_prepared;
  std::thread other([&] { reverse_prepared = pipeline.Register(t, s); });
  again = pipeline.Register(s, t);
  other.join();
  ExpectIdentical(direct, again);
  ExpectIdentical(reverse, reverse_prepared);

  // Prepared as sources only: the target's ICP geometry is made when it is first a target.
  const PreparedScan s_only = pipeline.Prepare(source, /*as_target=*/false);
  const PreparedScan t_only = pipeline.Prepare(target, /*as_target=*/false);
  ExpectIdentical(direct, pipeline.Register(s_only, t_only));
  ExpectIdentical(reverse, pipeline.Register(t_only, s_only));
}

INSTANTIATE_TEST_SUITE_P(RealFrames, PreparedScanTest,
                         ::testing::Values(RealPair{"7scenes-redkitchen", 20, 0},
                                           RealPair{"7scenes-redkitchen", 60, 0},
                                           RealPair{"hololens-office", 4, 3}));

TEST(PreparedScan, OneThreadAndTwoThreadsGiveTheSameTransformBitForBit) {
  // threads decides where the work runs (both scans at once, the geometry beside the models, the
  // ICP search split in two), never the result.
  PipelineConfig one, two;
  one.threads = 1;
  two.threads = 2;
  const Pipeline serial(one), parallel(two);
  for (const RealPair& p :
       {RealPair{"7scenes-redkitchen", 20, 0}, RealPair{"7scenes-redkitchen", 460, 400},
        RealPair{"hololens-office", 4, 3}}) {
    SCOPED_TRACE(p.dataset + " " + std::to_string(p.source) + " -> " + std::to_string(p.target));
    const Scan source = Frame(p.dataset, p.source), target = Frame(p.dataset, p.target);
    const RegistrationResult a = serial.Register(source, target);
    const RegistrationResult b = parallel.Register(source, target);
    EXPECT_TRUE(a.count_test_passed) << a.reason;  // ICP ran: its parallel search is compared
    ExpectIdentical(a, b);
  }
}

TEST(PreparedScan, RefusedByAnotherPipelineAndWhenEmpty) {
  const Pipeline a{PipelineConfig()}, b{PipelineConfig()};
  const PreparedScan s = a.Prepare(Frame("7scenes-redkitchen", 20));
  const PreparedScan t = a.Prepare(Frame("7scenes-redkitchen", 0));
  try {
    b.Register(s, t);
    FAIL() << "a prepared scan of another Pipeline was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("prepared by another Pipeline"), std::string::npos)
        << e.what();
  }
  try {
    a.Register(PreparedScan(), t);
    FAIL() << "an empty prepared scan was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("source prepared scan"), std::string::npos) << e.what();
  }
  Scan empty;
  empty.name = "nothing";
  EXPECT_THROW(a.Prepare(empty), InputError);
}

}  // namespace
}  // namespace zeroreg
