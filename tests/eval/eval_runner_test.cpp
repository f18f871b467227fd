// The pair runner with a fake method and in-memory scans: resume skips finished pairs, a
// truncated last line is dropped, --jobs 2 gives the records of --jobs 1, shards merged give the
// summary of a single run, and a results folder refuses another method's results.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "eval/protocols.hpp"
#include "eval/runner.hpp"
#include "eval/session.hpp"
#include "eval/summary.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

Transform Pose(double deg_z, double tx) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(deg_z * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T(0, 3) = tx;
  return T;
}

// Scan "k" has world pose Pose(k, 0.01 k); no images are needed by the fake method.
class FakeLoader : public ScanLoader {
 public:
  Scan Load(const std::string& ref) const override {
    Scan s;
    s.name = ref;
    const int k = std::stoi(ref);
    if (k < 0) throw InputError(ref + ": cannot be loaded");
    s.T_world_scan_gt = Pose(k, 0.01 * k);
    return s;
  }
};

// Returns the ground truth perturbed by a pair-dependent error (so pairs differ), counting calls.
class FakeMethod : public PairMethod {
 public:
  explicit FakeMethod(std::atomic<int>* calls) : calls_(calls) {}
  MethodOutput Run(const Scan& source, const Scan& target) override {
    ++*calls_;
    const int s = std::stoi(source.name), t = std::stoi(target.name);
    // The first pair is slow, so that with two jobs it finishes after the second one.
    if (t == 0) std::this_thread::sleep_for(std::chrono::milliseconds(30));
    MethodOutput o;
    const Transform gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
    o.T_target_source = gt * Pose(0.37 * ((s + t) % 11), 0.013 * (s % 7));
    o.valid = (s + t) % 3 != 0;
    Correspondence c;
    c.source = Eigen::Vector3d(0.1 * s, 0.2, 1.0);
    c.target = (gt * c.source.homogeneous()).head<3>();
    o.correspondences.push_back(c);
    return o;
  }

 private:
  std::atomic<int>* calls_;
};

std::vector<PairTask> Tasks(int n) {
  std::vector<int> frames;
  for (int k = 0; k < 10 * n + 20; ++k) frames.push_back(k);
  std::vector<PairTask> tasks = FramePairTasks(frames, 20, 10, 0, "unused", "fake");
  tasks.resize(n);
  for (PairTask& t : tasks) {
    t.target_ref = std::to_string(t.target_id);
    t.source_ref = std::to_string(t.source_id);
  }
  return tasks;
}

class EvalRunner : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshTestDir("zeroreg_eval_runner_");
    factory_ = [this]() { return std::make_unique<FakeMethod>(&calls_); };
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<PairRecord> Run(const std::vector<PairTask>& tasks, const std::string& out,
                              int jobs = 1, RunStats* stats = nullptr) {
    RunOptions options;
    options.jobs = jobs;
    options.progress = false;
    return RunPairs(tasks, "fake", factory_, loader_, (dir_ / out / "pairs.jsonl").string(),
                    options, stats);
  }
  static RunInfo Info(const std::vector<PairTask>& tasks, const std::string& shard = "0/1") {
    RunInfo info;
    info.protocol = "pairs";
    info.method = "fake";
    info.settings = {{"pipeline", {{"seed", 0}}}};
    info.tasks = tasks;
    info.shard = shard;
    return info;
  }

  fs::path dir_;
  std::atomic<int> calls_{0};
  MethodFactory factory_;
  FakeLoader loader_;
};

TEST_F(EvalRunner, ResumeSkipsFinishedPairsAndRetriesErrors) {
  std::vector<PairTask> tasks = Tasks(6);
  tasks[4].source_ref = "-1";  // cannot be loaded: recorded with an error
  RunStats stats;
  std::vector<PairTask> first_four(tasks.begin(), tasks.begin() + 4);
  EXPECT_EQ(Run(first_four, "r", 1, &stats).size(), 4u);
  EXPECT_EQ(calls_, 4);
  EXPECT_EQ(stats.ran, 4);

  // Restart over all six: only the two new ones run; the bad one is recorded with its error.
  const auto records = Run(tasks, "r", 1, &stats);
  EXPECT_EQ(calls_, 5);
  EXPECT_EQ(stats.reused, 4);
  EXPECT_EQ(stats.ran, 2);
  EXPECT_EQ(stats.errors, 1);
  ASSERT_EQ(records.size(), 6u);
  EXPECT_NE(records[4].error.find("cannot be loaded"), std::string::npos);
  EXPECT_EQ(records[5].key, tasks[5].Key());  // task order

  // The error is retried on the next restart (still failing), nothing else runs again; the
  // file reads in task order, the retry's record in place of the error it supersedes.
  Run(tasks, "r", 1, &stats);
  EXPECT_EQ(calls_, 5);
  EXPECT_EQ(stats.ran, 1);
  EXPECT_EQ(stats.reused, 5);
  EXPECT_EQ(DoneKeys((dir_ / "r" / "pairs.jsonl").string()).size(), 5u);
  const std::vector<PairRecord> lines = ReadPairsJsonl((dir_ / "r" / "pairs.jsonl").string());
  ASSERT_EQ(lines.size(), 6u);
  for (size_t k = 0; k < 6; ++k) EXPECT_EQ(lines[k].key, tasks[k].Key()) << k;
}

TEST_F(EvalRunner, TruncatedLastLineOfAKilledRunIsDroppedAndRerun) {
  const std::vector<PairTask> tasks = Tasks(3);
  Run(tasks, "r");
  const std::string path = (dir_ / "r" / "pairs.jsonl").string();
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  text.resize(text.size() - 40);  // the third line cut short
  std::ofstream(path, std::ios::trunc) << text;
  bool dropped = false;
  EXPECT_EQ(ReadPairsJsonl(path, &dropped).size(), 2u);
  EXPECT_TRUE(dropped);

  const auto records = Run(tasks, "r");
  EXPECT_EQ(calls_, 4);  // 3 + the re-run of the cut pair
  EXPECT_EQ(records.size(), 3u);
  EXPECT_EQ(ReadPairsJsonl(path, &dropped).size(), 3u);
  EXPECT_FALSE(dropped);
  // A corrupt line in the middle is an error naming the file and line.
  std::ofstream(path, std::ios::trunc) << "{bad\n" << text;
  EXPECT_THROW(ReadPairsJsonl(path), InputError);
}

TEST_F(EvalRunner, TwoJobsGiveTheRecordsOfOneJob) {
  const std::vector<PairTask> tasks = Tasks(12);
  const auto one = Run(tasks, "one", 1);
  const auto two = Run(tasks, "two", 2);
  ASSERT_EQ(one.size(), two.size());
  for (size_t k = 0; k < one.size(); ++k) {
    PairRecord a = one[k], b = two[k];
    a.time_ms = b.time_ms = 0;  // wall time differs
    EXPECT_EQ(PairRecordToJson(a), PairRecordToJson(b)) << k;
  }
  // The file, too, is in task order once the jobs are done (the slow first pair finished last).
  const std::string two_file = (dir_ / "two" / "pairs.jsonl").string();
  std::vector<PairRecord> lines = ReadPairsJsonl(two_file);
  ASSERT_EQ(lines.size(), tasks.size());
  for (size_t k = 0; k < tasks.size(); ++k) EXPECT_EQ(lines[k].key, tasks[k].Key()) << k;

  // A later run over other pairs puts them first, in its order, and keeps the other records.
  const std::vector<PairTask> rerun = {tasks[7], tasks[1]};
  std::vector<PairRecord> kept;
  for (const PairRecord& r : lines) {
    if (r.key != tasks[1].Key() && r.key != tasks[7].Key()) kept.push_back(r);
  }
  WritePairsJsonl(two_file, kept);  // as if pairs 1 and 7 had not finished
  Run(rerun, "two", 2);
  lines = ReadPairsJsonl(two_file);
  ASSERT_EQ(lines.size(), tasks.size());
  EXPECT_EQ(lines[0].key, tasks[7].Key());
  EXPECT_EQ(lines[1].key, tasks[1].Key());
  for (size_t k = 2; k < lines.size(); ++k) EXPECT_EQ(lines[k].key, kept[k - 2].key) << k;
}

TEST_F(EvalRunner, MergedShardsGiveTheSummaryOfASingleRun) {
  const std::vector<PairTask> tasks = Tasks(10);
  const std::string single = (dir_ / "single").string();
  static_cast<void>(PrepareOutDir(single, Info(tasks)));  // lock released at once
  const EvalSummary expected = WriteSummary(single, Info(tasks), tasks, Run(tasks, "single"));

  std::vector<std::string> shard_dirs;
  for (int i = 0; i < 3; ++i) {
    const std::string shard = std::to_string(i) + "/3";
    const std::string out = "shard-" + std::to_string(i);
    const std::vector<PairTask> mine = ApplyShard(tasks, ParseShard(shard));
    static_cast<void>(
        PrepareOutDir((dir_ / out).string(), Info(tasks, shard)));  // lock released at once
    WriteSummary((dir_ / out).string(), Info(tasks, shard), mine, Run(mine, out));
    shard_dirs.push_back((dir_ / out).string());
  }
  int missing = -1;
  const EvalSummary merged = MergeRuns(shard_dirs, (dir_ / "merged").string(), &missing);
  EXPECT_EQ(missing, 0);
  ASSERT_FALSE(expected.json["benchmarks"].empty());
  // time_ms differs between runs; everything else must be identical.
  auto without_time = [](nlohmann::json j) {
    for (auto& b : j) {
      b.erase("mean_time_s");
      b.erase("median_time_ms");
    }
    return j;
  };
  EXPECT_EQ(without_time(merged.json["benchmarks"]), without_time(expected.json["benchmarks"]));
  EXPECT_EQ(merged.json["shard"], "merged");
  EXPECT_EQ(ReadPairsJsonl((dir_ / "merged" / "pairs.jsonl").string()).size(), tasks.size());

  // Merging only two of the three shards reports the missing pairs.
  MergeRuns({shard_dirs[0], shard_dirs[1]}, (dir_ / "partial").string(), &missing);
  EXPECT_EQ(missing, static_cast<int>(ApplyShard(tasks, ParseShard("2/3")).size()));
}

TEST_F(EvalRunner, ResultsFolderRefusesAnotherMethodOrConfig) {
  const std::vector<PairTask> tasks = Tasks(2);
  const std::string out = (dir_ / "r").string();
  static_cast<void>(PrepareOutDir(out, Info(tasks)));     // lock released at once
  static_cast<void>(PrepareOutDir(out, Info(Tasks(1))));  // another selection: fine
  RunInfo other = Info(tasks);
  other.settings["pipeline"]["seed"] = 1;
  EXPECT_THROW(PrepareOutDir(out, other), InputError);
  other = Info(tasks);
  other.method = "fpfh";
  EXPECT_THROW(PrepareOutDir(out, other), InputError);
  // Shards of different selections cannot be merged.
  const std::string out2 = (dir_ / "r2").string();
  static_cast<void>(PrepareOutDir(out2, Info(Tasks(2))));  // lock released at once
  EXPECT_THROW(MergeRuns({out, out2}, (dir_ / "m").string()), InputError);

  // The pipeline's thread count decides no result: a folder resumes, and shards merge, under
  // another one.
  RunInfo threads = Info(tasks);
  threads.settings["pipeline"]["threads"] = 1;
  static_cast<void>(PrepareOutDir(out, threads));  // resumes
  const std::string out3 = (dir_ / "r3").string();
  threads.settings["pipeline"]["threads"] = 2;
  threads.shard = "1/2";
  static_cast<void>(PrepareOutDir(out3, threads));
  EXPECT_NO_THROW(MergeRuns({out, out3}, (dir_ / "m3").string()));
}

// A line written twice (a copy, an interrupted rewrite) is one record after a resume: the file
// holds one line per pair, in task order.
TEST_F(EvalRunner, DuplicatedLineIsOneRecordAfterAResume) {
  const std::vector<PairTask> tasks = Tasks(4);
  Run(tasks, "r");
  const std::string path = (dir_ / "r" / "pairs.jsonl").string();
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_EQ(lines.size(), 4u);
  {
    std::ofstream out(path, std::ios::app);
    out << lines[1] << "\n";
  }
  RunStats stats;
  const auto records = Run(tasks, "r", 1, &stats);
  EXPECT_EQ(stats.ran, 0);
  EXPECT_EQ(records.size(), 4u);
  std::vector<std::string> after;
  {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) after.push_back(line);
  }
  EXPECT_EQ(after, lines);
}

// `eval merge --out` onto a folder that holds another run's results is refused and leaves it as
// it was; a merge of the same run may be made again.
TEST_F(EvalRunner, MergeOntoAnotherRunIsRefused) {
  const std::vector<PairTask> tasks = Tasks(6);
  const std::string full = (dir_ / "full").string();
  static_cast<void>(PrepareOutDir(full, Info(tasks)));  // lock released at once
  WriteSummary(full, Info(tasks), tasks, Run(tasks, "full"));
  const std::string records = (dir_ / "full" / "pairs.jsonl").string();
  const std::vector<PairRecord> before = ReadPairsJsonl(records);

  const std::vector<PairTask> few = Tasks(2);
  const std::string shard = (dir_ / "few").string();
  static_cast<void>(PrepareOutDir(shard, Info(few)));
  WriteSummary(shard, Info(few), few, Run(few, "few"));
  try {
    MergeRuns({shard}, full);
    FAIL() << "merged over another run";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(full), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadPairsJsonl(records).size(), before.size());
  // A folder holding only pairs.jsonl (no run.json) is results too.
  const std::string bare = (dir_ / "bare").string();
  fs::create_directories(bare);
  WritePairsJsonl(bare + "/pairs.jsonl", before);
  EXPECT_THROW(MergeRuns({shard}, bare), InputError);
  EXPECT_EQ(ReadPairsJsonl(bare + "/pairs.jsonl").size(), before.size());
  // Merging again into the merge of the same run, or into an empty folder, is fine.
  const std::string merged = (dir_ / "merged").string();
  fs::create_directories(merged);
  EXPECT_NO_THROW(MergeRuns({shard}, merged));
  EXPECT_NO_THROW(MergeRuns({shard}, merged));
}

TEST_F(EvalRunner, RunJsonNamesTheZeroregVersion) {
  const std::string out = (dir_ / "v").string();
  static_cast<void>(PrepareOutDir(out, Info(Tasks(1))));  // lock released at once
  std::ifstream in(dir_ / "v" / "run.json");
  EXPECT_EQ(nlohmann::json::parse(in).at("zeroreg_version"), ZEROREG_VERSION);
}

TEST(EvalProgress, FormatsDurations) {
  EXPECT_EQ(FormatDuration(42.2), "42s");
  EXPECT_EQ(FormatDuration(185), "3m05s");
  EXPECT_EQ(FormatDuration(3720), "1h02m");
}

}  // namespace
}  // namespace zeroreg
