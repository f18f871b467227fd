// MergeRecordings and `zeroreg merge` on a short real split of redkitchen (frames 470-499 seen
// again at 600-640, ../shared/sessions/README.md), B unaligned: the transform against the truth,
// the outputs, the resume, the same answer from the CLI, and the refusal for two recordings that
// share nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eval/metrics.hpp"
#include "eval/sessions_protocol.hpp"
#include "recordings/open3d_baseline.hpp"
#include "rigid_motion.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

const std::string kA = "@460-499", kB = "@600-640";

Transform ReadMatrix(const std::string& path) {
  std::ifstream in(path);
  Transform T;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) in >> T(r, c);
  }
  EXPECT_TRUE(static_cast<bool>(in)) << path;
  return T;
}

class MergeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    a_ = ParseRecordingSpec(testing::RedkitchenDir() + kA);
    b_ = ParseRecordingSpec(testing::RedkitchenDir() + kB);
    truth_a_ = GroundTruthPoses(a_);
    truth_b_ = GroundTruthPoses(b_);
    a_.T_frame_camera = truth_a_;
    b_.T_frame_camera = Moved(T_Bframe_world_, truth_b_);
    config_.progress = false;
  }
  // The truth: B's frame -> world = A's frame.
  Transform TrueT_A_B() const { return T_Bframe_world_.inverse(); }

  const Transform T_Bframe_world_ = SeededUnalignment(0);
  RecordingInput a_, b_;
  std::map<int, Transform> truth_a_, truth_b_;
  RecordingsConfig config_;
};

TEST_F(MergeTest, PlacesBInAsFrameWithinTwoDegreesAndFiveCentimetres) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_");
  config_.out_dir = dir.string();
  const RecordingsResult r = MergeRecordings(a_, b_, config_);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_LE(RotationErrorDeg(r.T_A_B, TrueT_A_B()), 2.0);
  EXPECT_LE(TranslationErrorM(r.T_A_B, TrueT_A_B()), 0.05);
  EXPECT_LE(AbsoluteTrajectoryError(r.trajectories[1], truth_b_), 0.05);
  int accepted = 0;
  for (const LoopCandidateResult& c : r.candidates) {
    if (c.verdict != "accepted") continue;
    ++accepted;
    const Transform T_true =
        truth_a_.at(r.keyframes[c.u].frame).inverse() * truth_b_.at(r.keyframes[c.v].frame);
    EXPECT_LE(RotationErrorDeg(c.T_u_v, T_true), 5.0);
    EXPECT_LE(TranslationErrorM(c.T_u_v, T_true), 0.10);
  }
  EXPECT_GE(accepted, 2);
  for (const char* file :
       {"T_A_B.txt", "loops.jsonl", "loops.log", "keyframes.tsv", "trajectory_A.tum",
        "trajectory_B.tum", "merged.ply", "report.html", "summary.json"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  EXPECT_TRUE(ReadMatrix((dir / "T_A_B.txt").string()).isApprox(r.T_A_B, 1e-6));
  EXPECT_EQ(ReadLogFile((dir / "loops.log").string()).size(), static_cast<std::size_t>(accepted));
  EXPECT_EQ(ReadTumTrajectory((dir / "trajectory_B.tum").string()).size(), truth_b_.size());

  // A second run in the same folder registers nothing again and gives the same answer.
  const RecordingsResult again = MergeRecordings(a_, b_, config_);
  ASSERT_EQ(again.candidates.size(), r.candidates.size());
  for (const LoopCandidateResult& c : again.candidates) EXPECT_TRUE(c.resumed);
  EXPECT_TRUE(again.T_A_B.isApprox(r.T_A_B, 1e-9));

  // The CLI gives the same transform (with the truth's poses written as TUM trajectories: their
  // rounding and the pose graph's stopping tolerance move it by a fraction of a millimetre).
  WriteTumTrajectory((dir / "a.tum").string(), a_.T_frame_camera);
  WriteTumTrajectory((dir / "b.tum").string(), b_.T_frame_camera);
  const testing::CommandResult cli = testing::RunCli(
      "merge '" + testing::RedkitchenDir() + kA + "' '" + testing::RedkitchenDir() + kB +
      "' --poses-a '" + (dir / "a.tum").string() + "' --poses-b '" + (dir / "b.tum").string() +
      "' --out '" + (dir / "cli").string() + "' --quiet --no-cloud");
  ASSERT_EQ(cli.exit_code, 0) << cli.output;
  EXPECT_LE(RotationErrorDeg(ReadMatrix((dir / "cli/T_A_B.txt").string()), r.T_A_B), 0.01);
  EXPECT_LE(TranslationErrorM(ReadMatrix((dir / "cli/T_A_B.txt").string()), r.T_A_B), 0.001);
  fs::remove_all(dir);
}

TEST_F(MergeTest, ResumesAKilledRunFromItsVerifiedCandidates) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_");
  config_.out_dir = dir.string();
  config_.write_cloud = false;
  const RecordingsResult full = MergeRecordings(a_, b_, config_);
  ASSERT_GE(full.candidates.size(), 2u);
  // As a run killed after its first verified candidate leaves it: one line, the next cut short.
  std::ifstream in((dir / "loops.jsonl").string());
  std::string first;
  std::getline(in, first);
  in.close();
  std::ofstream((dir / "loops.jsonl").string()) << first << "\n{\"key\": \"0:4";
  fs::remove(dir / "T_A_B.txt");
  const RecordingsResult resumed = MergeRecordings(a_, b_, config_);
  int read_back = 0;
  for (const LoopCandidateResult& c : resumed.candidates) read_back += c.resumed;
  EXPECT_EQ(read_back, 1);
  EXPECT_EQ(resumed.found, full.found);
  EXPECT_TRUE(resumed.T_A_B.isApprox(full.T_A_B, 1e-9));
  EXPECT_TRUE(fs::exists(dir / "T_A_B.txt"));
  fs::remove_all(dir);
}

// Two registrations that no correspondence supports (zero inliers: placed by dense depth alone),
// planted among the real ones, agree with each other on a placement of B turned 30 degrees. They
// must not vote: counted as a second placement, they would make the merge refuse as ambiguous.
TEST_F(MergeTest, RegistrationsWithoutSupportingInliersDoNotVote) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_");
  config_.out_dir = dir.string();
  config_.write_cloud = false;
  config_.write_report = false;
  const RecordingsResult full = MergeRecordings(a_, b_, config_);
  ASSERT_TRUE(full.found) << full.reason;
  const Transform turned = testing::MakeTransform(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitY(),
                                                  Eigen::Vector3d::Zero()) *
                           TrueT_A_B();
  std::vector<nlohmann::json> records;
  {
    std::ifstream in((dir / "loops.jsonl").string());
    for (std::string line; std::getline(in, line);) records.push_back(nlohmann::json::parse(line));
  }
  // The planted two: candidates the real run did not accept, for two different B keyframes.
  std::vector<std::size_t> planted;
  for (std::size_t i = 0; i < records.size() && planted.size() < 2; ++i) {
    const LoopCandidateResult& c = full.candidates[i];
    if (c.verdict == "accepted") continue;
    if (!planted.empty() && full.candidates[planted[0]].v == c.v) continue;
    planted.push_back(i);
  }
  ASSERT_EQ(planted.size(), 2u) << "the short split has too few candidates left to plant on";
  for (std::size_t i : planted) {
    const LoopCandidateResult& c = full.candidates[i];
    const Transform T_u_v =
        full.keyframes[c.u].T_before.inverse() * turned * full.keyframes[c.v].T_before;
    records[i]["valid"] = true;
    records[i]["reason"] = "planted";
    records[i]["inliers"] = 0;
    records[i]["rotation_sigma_deg"] = nullptr;
    records[i]["translation_sigma_m"] = nullptr;
    records[i]["T_u_v"] = TransformToJson(T_u_v);
  }
  {
    std::ofstream out((dir / "loops.jsonl").string());
    for (const nlohmann::json& record : records) out << record.dump() << "\n";
  }
  const RecordingsResult r = MergeRecordings(a_, b_, config_);
  ASSERT_TRUE(r.found) << r.reason;
  for (std::size_t i : planted) EXPECT_EQ(r.candidates[i].verdict, "unsupported");
  EXPECT_LE(RotationErrorDeg(r.T_A_B, TrueT_A_B()), 2.0);
  EXPECT_LE(TranslationErrorM(r.T_A_B, TrueT_A_B()), 0.05);
  fs::remove_all(dir);
}

TEST_F(MergeTest, RefusesAFolderMadeWithOtherSettings) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_");
  std::ofstream((dir / "settings.json").string()) << "{\"command\": \"loops\"}\n";
  config_.out_dir = dir.string();
  EXPECT_THROW(MergeRecordings(a_, b_, config_), InputError);
  fs::remove_all(dir);
}

TEST(MergeCliTest, TwoRecordingsThatShareNothingGiveNoOverlapAndNoTransform) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_cli_");
  const testing::CommandResult r = testing::RunCli(
      "merge '" + testing::RedkitchenDir() + kA + "' '" + testing::SharedDir() +
      "/data/tum-fr3-cabinet@0-19' --out '" + dir.string() + "' --quiet --no-cloud");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no overlap found"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "T_A_B.txt"));
  EXPECT_TRUE(fs::exists(dir / "loops.jsonl"));
  fs::remove_all(dir);
}

TEST(MergeCliTest, BadRecordingsAreNamedWithExitTwo) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_cli_");
  testing::CommandResult r =
      testing::RunCli("merge '" + testing::RedkitchenDir() + "@50-20' '" +
                      testing::RedkitchenDir() + "' --out '" + dir.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("@50-20"), std::string::npos) << r.output;
  r = testing::RunCli("merge '" + testing::RedkitchenDir() + "@0-9' '" + testing::RedkitchenDir() +
                      "@20-29' --poses-b '" + dir.string() + "/missing.tum' --out '" +
                      dir.string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.tum"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

std::string FileText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(static_cast<bool>(in)) << path;
  return text.str();
}

// Two shards run at once (as GNU parallel or a job array runs them), then the last step reading
// their edge files: the edges and every output of one unsharded run, byte for byte. Then the
// shard arguments and edge files that cannot be used: exit 2, the argument named.
TEST(MergeCliTest, TwoShardsGiveTheEdgesAndTheResultOfOneRun) {
  const fs::path dir = testing::FreshTestDir("zeroreg_merge_shards_");
  const std::string cli = "'" + testing::CliPath() + "' merge '" + testing::RedkitchenDir() + kA +
                          "' '" + testing::RedkitchenDir() + kB + "' --quiet --no-cloud --out ";
  const std::string one = (dir / "one").string(), sharded = (dir / "sharded").string();
  testing::CommandResult r = testing::RunCommand(cli + "'" + one + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = testing::RunCommand(cli + "'" + sharded + "' --shard 1/2 & first=$!; " + cli + "'" + sharded +
                          "' --shard 2/2 & second=$!; wait $first && wait $second");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(fs::path(sharded) / "T_A_B.txt"));  // a shard decides nothing
  const std::string edges =
      " --edges '" + sharded + "/edges-1-of-2.jsonl' '" + sharded + "/edges-2-of-2.jsonl'";
  r = testing::RunCommand(cli + "'" + sharded + "'" + edges);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"loops.jsonl", "loops.log", "keyframes.tsv", "T_A_B.txt",
                           "trajectory_A.tum", "trajectory_B.tum"}) {
    EXPECT_EQ(FileText(fs::path(one) / file), FileText(fs::path(sharded) / file)) << file;
  }
  const nlohmann::json summary =
      nlohmann::json::parse(std::ifstream((fs::path(sharded) / "summary.json").string()));
  EXPECT_GT(summary.at("accepted").get<int>(), 1);

  const std::string other = "'" + (dir / "other").string() + "'";
  for (const std::string shard : {"0/2", "3/2", "2"}) {
    r = testing::RunCommand(cli + other + " --shard " + shard);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--shard " + shard + ": expected I/N"), std::string::npos) << r.output;
  }
  r = testing::RunCommand(cli + other + " --edges '" + sharded + "/edges-1-of-2.jsonl'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--edges: no edge file of shard 2/2"), std::string::npos) << r.output;
  r = testing::RunCommand(cli + other + edges + " '" + sharded + "/missing.jsonl'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.jsonl: cannot read"), std::string::npos) << r.output;
  r = testing::RunCommand(cli + other + edges + " --candidates 3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("made with other recordings or settings than this run "
                          "(candidates_per_keyframe differ)"),
            std::string::npos)
      << r.output;
  r = testing::RunCommand(cli + other + edges + " --shard 1/2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--shard and --edges"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

// The Open3D baseline on the short revisit: one fragment per recording (the recipe's 100 frames
// hold each), B placed by their FPFH + RANSAC + ICP edge; the nodes are the fragments' first
// frames.
TEST_F(MergeTest, Open3dBaselineFragmentsPlaceTheShortRevisit) {
  const RecordingsResult r = MergeWithOpen3dMultiway(a_, b_, config_);
  ASSERT_TRUE(r.found) << r.reason;
  ASSERT_EQ(r.keyframes.size(), 2u);
  EXPECT_EQ(r.keyframes[0].frame, 460);
  EXPECT_EQ(r.keyframes[1].frame, 600);
  EXPECT_LE(RotationErrorDeg(r.T_A_B, TrueT_A_B()), 2.0);
  EXPECT_LE(TranslationErrorM(r.T_A_B, TrueT_A_B()), 0.05);
  EXPECT_EQ(r.trajectories[1].size(), truth_b_.size());  // every frame of B placed
  RecordingInput no_poses = b_;
  no_poses.T_frame_camera.clear();
  EXPECT_THROW(MergeWithOpen3dMultiway(a_, no_poses, config_), InputError);
}

// `eval sessions` on a split file of the short revisit: the protocol's B unaligned by seed 0, the
// errors against the truth written per run and as a table.
TEST(EvalSessionsCliTest, MeasuresAShortSplit) {
  const fs::path dir = testing::FreshTestDir("zeroreg_eval_sessions_");
  std::ofstream((dir / "sessions.tsv").string())
      << "scene\tA\tB\n7scenes-redkitchen\t460-499\t600-640\n";
  const testing::CommandResult r = testing::RunCli(
      "eval sessions --sessions '" + (dir / "sessions.tsv").string() + "' --data '" +
      testing::SharedDir() + "/data' --modes unaligned --seeds 0-0 --out '" +
      (dir / "out").string() + "' --quiet --no-cloud");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json row = nlohmann::json::parse(
      std::ifstream((dir / "out/7scenes-redkitchen/unaligned-seed0/eval.json").string()));
  EXPECT_TRUE(row.at("found").get<bool>());
  EXPECT_LE(row.at("rot_err_deg").get<double>(), 2.0);
  EXPECT_LE(row.at("ate_b_after_cm").get<double>(), 5.0);
  EXPECT_EQ(row.at("accepted_wrong").get<int>(), 0);
  EXPECT_GT(row.at("loop_recall").get<double>(), 0.0);
  EXPECT_TRUE(row.at("stages").contains("verification"));
  EXPECT_NE(r.output.find("| 7scenes-redkitchen | unaligned | 0 | yes |"), std::string::npos)
      << r.output;
  fs::remove_all(dir);
}

// One sequence over the revisit (460-640), with odometry drifted five times the protocol's amount:
// the loop closures found are right, and the optimised trajectory is nearer the truth.
TEST(CloseLoopsTest, ClosesTheRevisitOfADriftedSequence) {
  RecordingInput sequence = ParseRecordingSpec(testing::RedkitchenDir() + "@460-640");
  const std::map<int, Transform> truth = GroundTruthPoses(sequence);
  sequence.T_frame_camera = DriftedOdometry(truth, 7, 0.05, 0.5);
  RecordingsConfig config;
  config.progress = false;
  config.min_separation = 3;
  const RecordingsResult r = CloseLoops(sequence, config);
  ASSERT_TRUE(r.found) << r.reason;
  int accepted = 0;
  for (const LoopCandidateResult& c : r.candidates) {
    if (c.verdict != "accepted") continue;
    ++accepted;
    const Transform T_true =
        truth.at(r.keyframes[c.u].frame).inverse() * truth.at(r.keyframes[c.v].frame);
    EXPECT_LE(RotationErrorDeg(c.T_u_v, T_true), 5.0);
    EXPECT_LE(TranslationErrorM(c.T_u_v, T_true), 0.10);
  }
  EXPECT_GE(accepted, 2);
  const double before = AbsoluteTrajectoryError(sequence.T_frame_camera, truth);
  const double after = AbsoluteTrajectoryError(r.trajectories[0], truth);
  EXPECT_LT(after, 0.5 * before) << "before " << before << " m, after " << after << " m";
}

}  // namespace
}  // namespace zeroreg
