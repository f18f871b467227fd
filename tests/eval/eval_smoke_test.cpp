// CI smoke runs of `zeroreg eval` on real redkitchen data, a handful of pairs per protocol (SIFT,
// so no model is needed). Every metric the runner reports is recomputed here from the per-pair
// JSON lines, the dataset's poses and the benchmark's gt.log / gt.info.
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "eval/metrics.hpp"
#include "eval/records.hpp"
#include "test_paths.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::RedkitchenDir;
using testing::RunCli;

class EvalSmoke : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::FreshTestDir("zeroreg_eval_smoke_"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Out(const std::string& name) const { return (dir_ / name).string(); }
  static json ReadJson(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
  }
  static std::string GtRoot() { return testing::SharedDir() + "/data/3dmatch-gt"; }
  // `eval pairs` over the first `limit` redkitchen pairs (i, i + 20) with SIFT features (no
  // model file, fast); the caller adds --out and options.
  static std::string SiftGap20(int limit, const std::string& options = "--no-progress") {
    return "eval pairs --data '" + RedkitchenDir() + "' --gap 20 --limit " + std::to_string(limit) +
           " --features sift " + options;
  }
  // Fragments are fused with a 4 cm TSDF voxel (a few CPU-seconds each instead of ~40 s at the
  // default 1 cm): this test checks the runner and the metrics, not the fusion's detail.
  std::string Cache() const { return (dir_ / "cache").string(); }

  fs::path dir_;
};

Transform Pose(int frame) {
  char name[64];
  std::snprintf(name, sizeof(name), "/frames/frame-%06d.pose.txt", frame);
  return ReadPoseFile(RedkitchenDir() + name);
}

TEST_F(EvalSmoke, FramePairsMetricsRecomputeFromTheJsonLines) {
  const std::string out = Out("pairs");
  const auto run = RunCli(SiftGap20(3) + " --out '" + out + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<PairRecord> records = ReadPairsJsonl(out + "/pairs.jsonl");
  ASSERT_EQ(records.size(), 3u);
  std::vector<double> rot, trans_cm;
  for (size_t k = 0; k < records.size(); ++k) {
    const PairRecord& r = records[k];
    // Pairs (0,20), (10,30), (20,40): target i, source i + 20.
    EXPECT_EQ(r.target_id, static_cast<int>(10 * k));
    EXPECT_EQ(r.source_id, static_cast<int>(10 * k + 20));
    const Transform gt = Pose(r.target_id).inverse() * Pose(r.source_id);
    EXPECT_LT((r.T_gt - gt).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(r.rotation_error_deg, RotationErrorDeg(r.T_est, gt), 1e-9);
    EXPECT_NEAR(r.translation_error_m, TranslationErrorM(r.T_est, gt), 1e-9);
    rot.push_back(r.rotation_error_deg);
    trans_cm.push_back(100 * r.translation_error_m);
  }
  // 20-frame gaps move the camera by ~6 deg / 14 cm; a right-way-round estimate is far closer
  // (a swapped source/target would show twice the motion).
  std::vector<double> sorted = rot;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_LT(sorted[1], 5.0);

  const json s = ReadJson(out + "/summary.json")["benchmarks"][0];
  EXPECT_EQ(s["benchmark"], "frames-g20");
  EXPECT_EQ(s["done"], 3);
  auto fraction_below = [](const std::vector<double>& v, double t) {
    return std::count_if(v.begin(), v.end(), [&](double e) { return e < t; }) / 3.0;
  };
  EXPECT_DOUBLE_EQ(s["rotation_accuracy_deg"]["5"].get<double>(), fraction_below(rot, 5));
  EXPECT_DOUBLE_EQ(s["rotation_accuracy_deg"]["45"].get<double>(), fraction_below(rot, 45));
  EXPECT_DOUBLE_EQ(s["translation_accuracy_cm"]["10"].get<double>(), fraction_below(trans_cm, 10));
  EXPECT_NEAR(s["rotation_error_deg"]["mean"].get<double>(), (rot[0] + rot[1] + rot[2]) / 3, 1e-9);
  EXPECT_NEAR(s["rotation_error_deg"]["median"].get<double>(), sorted[1], 1e-9);
  EXPECT_NE(run.output.find("| frames-g20 | 3 | 3 |"), std::string::npos) << run.output;

  // Restarting the same command evaluates nothing again.
  const auto again = RunCli(SiftGap20(3) + " --out '" + out + "'");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("0 pairs evaluated now, 3 reused"), std::string::npos)
      << again.output;
  // ... but another config in the same folder is refused.
  const auto other = RunCli(SiftGap20(3, "--seed 7 --no-progress") + " --out '" + out + "'");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("another config"), std::string::npos) << other.output;
}

TEST_F(EvalSmoke, ShardsMergedThroughTheCliEqualTheSingleRun) {
  const std::string common = SiftGap20(3);
  ASSERT_EQ(RunCli(common + " --out '" + Out("all") + "'").exit_code, 0);
  ASSERT_EQ(RunCli(common + " --shard 0/2 --out '" + Out("s0") + "'").exit_code, 0);
  ASSERT_EQ(RunCli(common + " --shard 1/2 --out '" + Out("s1") + "'").exit_code, 0);
  EXPECT_EQ(ReadPairsJsonl(Out("s0") + "/pairs.jsonl").size(), 2u);
  EXPECT_EQ(ReadPairsJsonl(Out("s1") + "/pairs.jsonl").size(), 1u);
  const auto merge =
      RunCli("eval merge '" + Out("s0") + "' '" + Out("s1") + "' --out '" + Out("m") + "'");
  ASSERT_EQ(merge.exit_code, 0) << merge.output;
  json a = ReadJson(Out("all") + "/summary.json")["benchmarks"];
  json b = ReadJson(Out("m") + "/summary.json")["benchmarks"];
  for (json* j : {&a, &b}) {
    (*j)[0].erase("mean_time_s");
    (*j)[0].erase("median_time_ms");
  }
  EXPECT_EQ(a, b);
}

// --jobs defaults to one job per processor the process may use, and the jobs share the
// processors; the records, and the file's line order, are those of --jobs 1 whatever the machine's
// core count (--jobs 3 runs several jobs even on one processor).
TEST_F(EvalSmoke, DefaultJobsGiveTheRecordsOfOneJob) {
  const std::string common = SiftGap20(4);
  ASSERT_EQ(RunCli(common + " --jobs 1 --out '" + Out("one") + "'").exit_code, 0);
  ASSERT_EQ(RunCli(common + " --out '" + Out("auto") + "'").exit_code, 0);
  ASSERT_EQ(RunCli(common + " --jobs 3 --out '" + Out("three") + "'").exit_code, 0);
  const std::vector<PairRecord> one = ReadPairsJsonl(Out("one") + "/pairs.jsonl");
  ASSERT_EQ(one.size(), 4u);
  for (const std::string name : {"auto", "three"}) {
    const std::vector<PairRecord> other = ReadPairsJsonl(Out(name) + "/pairs.jsonl");
    ASSERT_EQ(other.size(), one.size()) << name;
    for (size_t k = 0; k < one.size(); ++k) {
      PairRecord a = one[k], b = other[k];
      a.time_ms = b.time_ms = 0;  // wall time differs
      EXPECT_EQ(PairRecordToJson(a), PairRecordToJson(b)) << name << " line " << k;
    }
  }
  const auto negative = RunCli(common + " --jobs -1 --out '" + Out("neg") + "'");
  EXPECT_EQ(negative.exit_code, 2) << negative.output;
  EXPECT_NE(negative.output.find("--jobs"), std::string::npos) << negative.output;

  // Each pipeline gets processors / jobs threads (jobs: at most one per pair), at least 1, at most
  // the default 2; the config's own `threads` wins. No record depends on it, so a folder resumes
  // under another `threads` (3: never what the sharing gives).
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  ASSERT_EQ(sched_getaffinity(0, sizeof(allowed), &allowed), 0);
  const int processors = CPU_COUNT(&allowed);
  const auto threads = [&](const std::string& name) {
    return ReadJson(Out(name) + "/run.json")["settings"]["pipeline"]["threads"].get<int>();
  };
  const auto shared = [&](int jobs) { return std::min(2, std::max(1, processors / jobs)); };
  EXPECT_EQ(threads("one"), shared(1));
  EXPECT_EQ(threads("auto"), shared(std::min(processors, 4)));
  EXPECT_EQ(threads("three"), shared(3));
  const auto resumed = RunCli(common + " --set threads=3 --out '" + Out("auto") + "'");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("0 pairs evaluated now, 4 reused"), std::string::npos)
      << resumed.output;
  EXPECT_EQ(threads("auto"), 3);

  // The progress says how the run uses the machine.
  const auto shown = RunCli(SiftGap20(4, "--jobs 3") + " --out '" + Out("progress") + "'");
  ASSERT_EQ(shown.exit_code, 0) << shown.output;
  const std::string label =
      "zeroreg, 3 jobs x " + std::to_string(shared(3)) + (shared(3) == 1 ? " thread" : " threads");
  EXPECT_NE(shown.output.find(label), std::string::npos) << shown.output;
}

TEST_F(EvalSmoke, PairListRunWritesEstLogAndScoresAgainstGtLog) {
  const std::string list = testing::SharedDir() + "/lists/hololens-gap1";
  const std::string data = testing::SharedDir() + "/data/hololens-office";
  const std::string out = Out("list");
  const std::string command = "eval pairs --list '" + list + "' --data '" + data +
                              "' --limit 3 --method sift --jobs 2 --no-progress --out '";
  const auto run = RunCli(command + out + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<LogEntry> gt = ReadLogFile(list + "/gt.log");
  const std::vector<LogEntry> est = ReadLogFile(out + "/est.log");
  ASSERT_EQ(est.size(), 3u);
  std::vector<PairRecord> records = ReadPairsJsonl(out + "/pairs.jsonl");
  ASSERT_EQ(records.size(), 3u);
  std::sort(records.begin(), records.end(),
            [](const PairRecord& a, const PairRecord& b) { return a.target_id < b.target_id; });
  for (size_t k = 0; k < 3; ++k) {
    // pairs.txt order (3 4, 6 7, 9 10); the ground truth is gt.log's matrix.
    EXPECT_EQ(est[k].i, gt[k].i);
    EXPECT_EQ(est[k].j, gt[k].j);
    EXPECT_EQ(records[k].target_id, gt[k].i);
    EXPECT_EQ(records[k].T_gt, gt[k].T_i_j);
    EXPECT_EQ(est[k].T_i_j, records[k].T_est);
    EXPECT_EQ(records[k].path, "sift");
  }
  const json s = ReadJson(out + "/summary.json")["benchmarks"][0];
  EXPECT_EQ(s["benchmark"], "hololens-gap1");
  EXPECT_EQ(s["done"], 3);
  EXPECT_EQ(s["valid_right"].get<int>() + s["valid_wrong"].get<int>() +
                s["invalid_right"].get<int>() + s["invalid_wrong"].get<int>(),
            3);
  EXPECT_DOUBLE_EQ(s["object_path_share"].get<double>(), 0.0);
  // Two shards merged give the same est.log (in pairs.txt order) and confusion.
  ASSERT_EQ(RunCli(command + Out("s0") + "' --shard 0/2").exit_code, 0);
  ASSERT_EQ(RunCli(command + Out("s1") + "' --shard 1/2").exit_code, 0);
  const auto merge =
      RunCli("eval merge '" + Out("s0") + "' '" + Out("s1") + "' --out '" + Out("m") + "'");
  ASSERT_EQ(merge.exit_code, 0) << merge.output;
  const std::vector<LogEntry> merged = ReadLogFile(Out("m") + "/est.log");
  ASSERT_EQ(merged.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(merged[k].i, est[k].i);
    EXPECT_EQ(merged[k].j, est[k].j);
    EXPECT_EQ(merged[k].T_i_j, est[k].T_i_j);
  }
  const json m = ReadJson(Out("m") + "/summary.json")["benchmarks"][0];
  EXPECT_EQ(m["valid_right"], s["valid_right"]);
  EXPECT_EQ(m["success"], s["success"]);
  // --list and --gap exclude each other; a resumed folder refuses another list.
  const auto both = RunCli(command + Out("y") + "' --gap 5");
  EXPECT_NE(both.exit_code, 0) << both.output;
  EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
  const auto other =
      RunCli("eval pairs --list '" + testing::SharedDir() + "/lists/hololens-gap5' --data '" +
             data + "' --limit 3 --method sift --no-progress --out '" + out + "'");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("another config or data"), std::string::npos) << other.output;
}

TEST_F(EvalSmoke, ThreeDMatchFusesOnlyNeededFragmentsAndScoresLikeTheGroundTruthFiles) {
  const std::string out = Out("3dmatch");
  // --limit 2: gt.log's first two pairs, "0 1" (consecutive) and "0 2": fragments 0, 1, 2.
  const auto run = RunCli("eval 3dmatch --data '" + RedkitchenDir() + "' --gt '" + GtRoot() +
                          "' --cache '" + Cache() +
                          "' --fuse-voxel 0.04 --jobs 2 --limit 2 --features sift --no-progress "
                          "--out '" +
                          out + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("fragments: 3 needed"), std::string::npos) << run.output;

  const std::vector<LogEntry> gt_log =
      ReadLogFile(GtRoot() + "/3DMatch/7-scenes-redkitchen/gt.log");
  const std::vector<InfoEntry> gt_info =
      ReadInfoFile(GtRoot() + "/3DMatch/7-scenes-redkitchen/gt.info");
  // pairs.jsonl is in finishing order (--jobs 2); est.log and the checks below in gt.log order.
  std::vector<PairRecord> records = ReadPairsJsonl(out + "/pairs.jsonl");
  ASSERT_EQ(records.size(), 2u);
  std::sort(records.begin(), records.end(), [](const PairRecord& a, const PairRecord& b) {
    return std::make_pair(a.target_id, a.source_id) < std::make_pair(b.target_id, b.source_id);
  });
  const std::vector<LogEntry> est = ReadLogFile(out + "/3DMatch/7-scenes-redkitchen/est.log");
  ASSERT_EQ(est.size(), 2u);
  int registered = 0, matched = 0;
  double ir_sum = 0;
  for (size_t k = 0; k < 2; ++k) {
    const PairRecord& r = records[k];
    EXPECT_EQ(r.target_id, gt_log[k].i);
    EXPECT_EQ(r.source_id, gt_log[k].j);
    EXPECT_EQ(r.T_gt, gt_log[k].T_i_j);
    // est.log holds the scored estimate, as an independent scorer reads it.
    EXPECT_EQ(est[k].i, r.target_id);
    EXPECT_EQ(est[k].j, r.source_id);
    EXPECT_EQ(est[k].n, 60);
    EXPECT_EQ(est[k].T_i_j, r.T_est);
    const double E = RegistrationRecallError(est[k].T_i_j, gt_log[k].T_i_j, gt_info[k].information);
    ASSERT_TRUE(r.recall_error.has_value());
    EXPECT_NEAR(*r.recall_error, E, 1e-12);
    EXPECT_EQ(r.registered, E <= 0.04);
    if (!r.consecutive && r.registered) ++registered;
    ir_sum += r.inlier_ratio;
    if (r.inlier_ratio > 0.05) ++matched;
  }
  EXPECT_TRUE(records[0].consecutive);
  EXPECT_FALSE(records[1].consecutive);
  const json s = ReadJson(out + "/summary.json")["benchmarks"][0];
  EXPECT_EQ(s["benchmark"], "3DMatch");
  EXPECT_EQ(s["evaluated"], 1);
  EXPECT_EQ(s["registered"], registered);
  EXPECT_DOUBLE_EQ(s["registration_recall"].get<double>(), registered / 1.0);
  EXPECT_NEAR(s["inlier_ratio"].get<double>(), ir_sum / 2, 1e-12);
  EXPECT_DOUBLE_EQ(s["feature_match_recall"].get<double>(), matched / 2.0);
  // The fused fragments are cached where the runner said, keyed by the fusion settings.
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(fs::exists(Cache() + "/7-scenes-redkitchen/voxel-40mm/fragment-" +
                           std::to_string(k) + "/scan.json"));
  }
  // Another depth scale makes other fragments: the folder refuses to resume with it.
  const auto other_scale = RunCli("eval 3dmatch --data '" + RedkitchenDir() + "' --gt '" +
                                  GtRoot() + "' --cache '" + Cache() +
                                  "' --fuse-voxel 0.04 --depth-scale 2000 --limit 2 --features "
                                  "sift --no-progress --out '" +
                                  out + "'");
  EXPECT_EQ(other_scale.exit_code, 2) << other_scale.output;
  EXPECT_EQ(ReadPairsJsonl(out + "/pairs.jsonl").size(), 2u);
}

// The TUM cabinet is a box: from 8 frames apart, 10 -> 18 comes back valid and turned 89 deg
// without a prior, since the check cannot tell the box's sides apart (BENCHMARKS.md "Pairs that
// share nothing, or little"). A prior 5 deg / 10 cm from the truth, as odometry would give, must
// leave no wrong pose valid; each pair gets the same prior with any --jobs, and the prior is part
// of what a results folder holds.
TEST_F(EvalSmoke, MotionPriorFromTheTruthLeavesNoWrongPoseValid) {
  const std::string pairs = Out("pairs.txt");
  std::ofstream(pairs) << "10 18\n12 20\n";
  const std::string common = "eval pairs --data '" + testing::SharedDir() +
                             "/data/tum-fr3-cabinet' --gap 8 --step 1 --pairs '" + pairs +
                             "' --prior-error-deg 5 --prior-error-m 0.1 --no-progress";
  const auto run = RunCli(common + " --jobs 1 --out '" + Out("one") + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<PairRecord> one = ReadPairsJsonl(Out("one") + "/pairs.jsonl");
  ASSERT_EQ(one.size(), 2u);
  for (const PairRecord& r : one) {
    const bool right = r.rotation_error_deg < 15 && r.translation_error_m < 0.3;
    EXPECT_TRUE(right || !r.valid) << r.key << ": valid and " << r.rotation_error_deg << " deg off";
  }
  const json prior = ReadJson(Out("one") + "/run.json")["settings"]["prior"];
  EXPECT_DOUBLE_EQ(prior["rotation_deg"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(prior["translation_m"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(prior["max_rotation_deg"].get<double>(), 15.0);

  // The same records with two jobs and without the prepared-scan cache.
  ASSERT_EQ(RunCli(common + " --jobs 2 --out '" + Out("two") + "'").exit_code, 0);
  ASSERT_EQ(RunCli(common + " --prepared-cache 0 --out '" + Out("uncached") + "'").exit_code, 0);
  for (const std::string name : {"two", "uncached"}) {
    const std::vector<PairRecord> other = ReadPairsJsonl(Out(name) + "/pairs.jsonl");
    ASSERT_EQ(other.size(), one.size()) << name;
    for (size_t k = 0; k < one.size(); ++k) {
      PairRecord a = one[k], b = other[k];
      a.time_ms = b.time_ms = 0;
      EXPECT_EQ(PairRecordToJson(a), PairRecordToJson(b)) << name << " line " << k;
    }
  }
  // The whole-image method takes the prior too; ICP from the prior ("prior icp", when no image
  // pose is valid within it) is part of that, not a wrong path.
  const auto image = RunCli(common + " --method image --out '" + Out("image") + "'");
  ASSERT_EQ(image.exit_code, 0) << image.output;
  for (const PairRecord& r : ReadPairsJsonl(Out("image") + "/pairs.jsonl")) {
    EXPECT_EQ(r.error, "") << r.key;
    const bool right = r.rotation_error_deg < 15 && r.translation_error_m < 0.3;
    EXPECT_TRUE(right || !r.valid) << r.key << ": valid and " << r.rotation_error_deg << " deg off";
  }
  // Another prior is another run: the folder refuses it rather than mixing the two. An error
  // beyond the tolerance is allowed, with a warning that no right pose can then be valid.
  const auto other = RunCli("eval pairs --data '" + testing::SharedDir() +
                            "/data/tum-fr3-cabinet' --gap 8 --step 1 " + "--pairs '" + pairs +
                            "' --prior-error-deg 20 --no-progress --out '" + Out("one") + "'");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("another config or data settings"), std::string::npos)
      << other.output;
  EXPECT_NE(other.output.find("exceeds its tolerance"), std::string::npos) << other.output;
}

TEST_F(EvalSmoke, BadArgumentsAreClearErrors) {
  const std::string data = "--data '" + RedkitchenDir() + "' ";
  auto expect_error = [&](const std::string& args, const std::string& text) {
    const auto r = RunCli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << args << "\n" << r.output;
  };
  expect_error("eval pairs " + data + "--method icp --out '" + Out("x") + "'", "unknown method");
  expect_error("eval pairs " + data + "--shard 2/2 --features sift --out '" + Out("x") + "'",
               "--shard 2/2");
  expect_error("eval 3dmatch " + data + "--gt '" + Out("nowhere") + "' --out '" + Out("x") + "'",
               "gt.log");
  expect_error("eval 3dmatch " + data + "--gt '" + GtRoot() + "' --benchmarks 3DFoo --out '" +
                   Out("x") + "'",
               "unknown benchmark");
  expect_error("eval merge '" + Out("nothing") + "' --out '" + Out("m") + "'", "run.json");
  expect_error("eval pairs " + data + "--method sift --prior-error-deg 5 --out '" + Out("x") + "'",
               "the sift baseline takes no motion prior");
  expect_error("eval pairs " + data + "--prior-max-rotation-deg 10 --out '" + Out("x") + "'",
               "a tolerance needs a prior");
  expect_error("eval pairs " + data + "--prior-error-m -0.1 --out '" + Out("x") + "'",
               "--prior-error-m");
  expect_error("eval pairs " + data + "--prior-error-m inf --out '" + Out("x") + "'",
               "--prior-error-m");
  expect_error("eval pairs " + data + "--prior-error-deg 5 --prior-max-rotation-deg nan --out '" +
                   Out("x") + "'",
               "--prior-max-rotation-deg");
  expect_error("eval pairs " + data + "--prior-error-deg 5 --prior-max-translation-m 0 --out '" +
                   Out("x") + "'",
               "expected a positive number");
}

}  // namespace
}  // namespace zeroreg
