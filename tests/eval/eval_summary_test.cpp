// Aggregate metrics of the evaluation runner against values computed by hand, per-pair records,
// est.log and the pair-selection helpers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "eval/fragments.hpp"
#include "eval/object_match_metrics.hpp"
#include "eval/protocols.hpp"
#include "eval/records.hpp"
#include "eval/summary.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

Transform Pose(double deg_z, double tx, double ty, double tz) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(deg_z * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.topRightCorner<3, 1>() << tx, ty, tz;
  return T;
}

PairTask MatchTask(const std::string& benchmark, int i, int j, const Transform& gt) {
  PairTask t;
  t.benchmark = benchmark;
  t.scene = "scene";
  t.target_id = i;
  t.source_id = j;
  t.T_target_source_gt = gt;
  t.information = InformationMatrix::Identity();
  t.log_n = 60;
  t.consecutive = j == i + 1;
  return t;
}

// `good` correspondences consistent with `gt` and `bad` ones 1 m off.
std::vector<Correspondence> Correspondences(const Transform& gt, int good, int bad) {
  std::vector<Correspondence> c;
  for (int k = 0; k < good + bad; ++k) {
    Correspondence x;
    x.source = Eigen::Vector3d(0.1 * k, 0.2, 1.0);
    x.target = (gt * x.source.homogeneous()).head<3>();
    if (k >= good) x.target.x() += 1.0;
    c.push_back(x);
  }
  return c;
}

MethodOutput Output(const Transform& T, std::vector<Correspondence> c) {
  MethodOutput o;
  o.T_target_source = T;
  o.valid = true;
  o.path = "object";
  o.correspondences = std::move(c);
  return o;
}

std::string TempDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("zeroreg_eval_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

TEST(EvalSummary, OneSuccessOneFailureOneConsecutiveGiveRecallOneHalf) {
  const Transform gt = Pose(30, 0.5, -0.2, 0.1);
  const PairTask a = MatchTask("3DMatch", 0, 2, gt);  // success: 2 deg, 3 cm off
  const PairTask b = MatchTask("3DMatch", 0, 3, gt);  // failure: 0.5 m off
  const PairTask c = MatchTask("3DMatch", 0, 1, gt);  // consecutive: never counted in RR
  const Transform near = gt * Pose(2, 0.03, 0, 0);
  const Transform far = gt * Pose(0, 0.5, 0, 0);
  MethodOutput fallback = Output(far, Correspondences(gt, 1, 0));
  fallback.path = "image-fallback";
  const std::vector<PairRecord> records = {
      ScorePair(a, "m", Output(near, Correspondences(gt, 3, 1)), gt, 1000),
      ScorePair(b, "m", Output(far, Correspondences(gt, 0, 10)), gt, 3000),
      ScorePair(c, "m", fallback, gt, 2000)};
  // By hand, with Info = I: E = |t|^2 + |q_xyz|^2 of inv(gt) * est.
  ASSERT_TRUE(records[0].recall_error.has_value());
  EXPECT_NEAR(*records[0].recall_error, 0.03 * 0.03 + std::pow(std::sin(M_PI / 180.0), 2), 1e-8);
  EXPECT_NEAR(*records[1].recall_error, 0.25, 1e-8);
  EXPECT_TRUE(records[0].registered);
  EXPECT_FALSE(records[1].registered);

  const auto summaries = SummarizeMatch({a, b, c}, records);
  ASSERT_EQ(summaries.size(), 1u);
  const MatchBenchmarkSummary& s = summaries[0];
  EXPECT_EQ(s.num_pairs, 3);
  EXPECT_EQ(s.num_done, 3);
  EXPECT_EQ(s.num_evaluated, 2);
  EXPECT_EQ(s.num_registered, 1);
  EXPECT_DOUBLE_EQ(s.registration_recall, 0.5);
  // IR over every finished pair (consecutive included): (3/4 + 0 + 1) / 3; FMR: 2 of 3 > 0.05.
  EXPECT_NEAR(s.inlier_ratio, (0.75 + 0.0 + 1.0) / 3.0, 1e-12);
  EXPECT_NEAR(s.feature_match_recall, 2.0 / 3.0, 1e-12);
  // RE / TE over the registered evaluated pairs only: pair a.
  EXPECT_EQ(s.rotation_error_deg.count, 1);
  EXPECT_NEAR(s.rotation_error_deg.mean, 2.0, 1e-5);
  EXPECT_NEAR(s.translation_error_cm.median, 3.0, 1e-5);
  EXPECT_NEAR(s.mean_time_s, 2.0, 1e-12);
  EXPECT_EQ(s.num_valid, 3);
  EXPECT_EQ(s.paths, (std::map<std::string, int>{{"object", 2}, {"image-fallback", 1}}));
  EXPECT_NE(MatchSummaryMarkdown(summaries).find("| image-fallback 1, object 2 |"),
            std::string::npos);
}

TEST(EvalSummary, MissingPairsCountAsFailuresAndScenesAreAveraged) {
  const Transform gt = Pose(10, 0.1, 0.2, 0.3);
  std::vector<PairTask> tasks;
  std::vector<PairRecord> records;
  // Scene x: 2 evaluated pairs, both registered. Scene y: 4 evaluated pairs, 1 registered, and
  // one of the failures has no record at all.
  for (int j = 2; j <= 3; ++j) {
    tasks.push_back(MatchTask("3DLoMatch", 0, j, gt));
    tasks.back().scene = "x";
    records.push_back(ScorePair(tasks.back(), "m", Output(gt, {}), gt, 0));
  }
  for (int j = 2; j <= 5; ++j) {
    tasks.push_back(MatchTask("3DLoMatch", 0, j, gt));
    tasks.back().scene = "y";
    if (j == 5) continue;  // missing
    records.push_back(
        ScorePair(tasks.back(), "m", Output(j == 2 ? gt : Pose(0, 0, 0, 0), {}), gt, 0));
  }
  const MatchBenchmarkSummary s = SummarizeMatch(tasks, records).at(0);
  EXPECT_EQ(s.num_scenes, 2);
  EXPECT_EQ(s.num_evaluated, 6);
  EXPECT_EQ(s.num_done, 5);
  EXPECT_EQ(s.num_registered, 3);
  // Per scene: 2/2 and 1/4, averaged: 0.625 (not 3/6).
  EXPECT_DOUBLE_EQ(s.registration_recall, 0.625);
}

TEST(EvalSummary, FramePairAccuraciesMeansAndMedians) {
  const Transform gt = Pose(5, 0.1, 0, 0);
  std::vector<PairTask> tasks;
  std::vector<PairRecord> records;
  // Rotation errors 1, 7, 20, 50 deg; translation errors 2, 8, 12, 30 cm.
  const double rot[] = {1, 7, 20, 50}, trans[] = {0.02, 0.08, 0.12, 0.30};
  for (int k = 0; k < 4; ++k) {
    PairTask t;
    t.benchmark = "frames-g20";
    t.scene = "s";
    t.target_id = 10 * k;
    t.source_id = 10 * k + 20;
    tasks.push_back(t);
    records.push_back(ScorePair(t, "m", Output(gt * Pose(rot[k], trans[k], 0, 0), {}), gt, 0));
  }
  const FramePairSummary s = SummarizeFramePairs(tasks, records).at(0);
  EXPECT_EQ(s.num_done, 4);
  ASSERT_EQ(s.rotation_accuracy.size(), 3u);
  EXPECT_DOUBLE_EQ(s.rotation_accuracy[0], 0.25);     // < 5 deg
  EXPECT_DOUBLE_EQ(s.rotation_accuracy[1], 0.50);     // < 10 deg
  EXPECT_DOUBLE_EQ(s.rotation_accuracy[2], 0.75);     // < 45 deg
  EXPECT_DOUBLE_EQ(s.translation_accuracy[0], 0.25);  // < 5 cm
  EXPECT_DOUBLE_EQ(s.translation_accuracy[1], 0.50);  // < 10 cm
  EXPECT_DOUBLE_EQ(s.translation_accuracy[2], 0.75);  // < 25 cm
  EXPECT_NEAR(s.rotation_error_deg.mean, 19.5, 1e-5);
  EXPECT_NEAR(s.rotation_error_deg.median, 13.5, 1e-5);
  EXPECT_NEAR(s.translation_error_cm.mean, 13.0, 1e-5);
  EXPECT_NEAR(s.translation_error_cm.median, 10.0, 1e-5);
  const std::string md = FramePairSummaryMarkdown({s});
  EXPECT_NE(md.find("| frames-g20 | 4 | 4 | 25.0 / 50.0 / 75.0 | 19.50 / 13.50 |"),
            std::string::npos)
      << md;
}

TEST(EvalSummary, FramePairSuccessConfusionObjectShareAndMedianTime) {
  const Transform gt = Pose(5, 0.1, 0, 0);
  std::vector<PairTask> tasks;
  std::vector<PairRecord> records;
  // (rotation error deg, translation error m, valid, path, time ms):
  //   right = RE < 15 deg and TE < 30 cm.
  struct Case {
    double rot, trans;
    bool valid;
    const char* path;
    double ms;
  };
  const Case cases[] = {
      {1, 0.02, true, "object", 100},           // valid, right
      {14.9, 0.29, true, "object", 300},        // valid, right (just inside)
      {16, 0.02, true, "image-fallback", 200},  // valid, WRONG (rotation)
      {1, 0.31, true, "object", 400},           // valid, WRONG (translation)
      {2, 0.05, false, "image", 500},           // invalid, right
      {40, 1.0, false, "object-centroids", 50}  // invalid, wrong
  };
  for (size_t k = 0; k < std::size(cases); ++k) {
    PairTask t;
    t.benchmark = "list";
    t.scene = "s";
    t.target_id = static_cast<int>(k);
    t.source_id = static_cast<int>(k) + 1;
    tasks.push_back(t);
    MethodOutput o = Output(gt * Pose(cases[k].rot, cases[k].trans, 0, 0), {});
    o.valid = cases[k].valid;
    o.path = cases[k].path;
    records.push_back(ScorePair(t, "m", o, gt, cases[k].ms));
  }
  PairTask missing;  // selected but not finished: counts nowhere
  missing.benchmark = "list";
  missing.scene = "s";
  missing.target_id = 100;
  missing.source_id = 101;
  tasks.push_back(missing);

  const FramePairSummary s = SummarizeFramePairs(tasks, records).at(0);
  EXPECT_EQ(s.num_done, 6);
  EXPECT_DOUBLE_EQ(s.success, 3.0 / 6.0);
  EXPECT_EQ(s.verdicts.valid_right, 2);
  EXPECT_EQ(s.verdicts.valid_wrong, 2);
  EXPECT_EQ(s.verdicts.invalid_right, 1);
  EXPECT_EQ(s.verdicts.invalid_wrong, 1);
  EXPECT_DOUBLE_EQ(s.object_path_share, 3.0 / 6.0);
  EXPECT_EQ(s.paths.at("object"), 3);
  EXPECT_DOUBLE_EQ(s.median_time_ms, 250.0);  // of 50 100 200 300 400 500
  const nlohmann::json j = ToJson(s);
  EXPECT_EQ(j["valid_wrong"], 2);
  EXPECT_EQ(j["invalid_right"], 1);
  EXPECT_DOUBLE_EQ(j["success"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["object_path_share"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["median_time_ms"].get<double>(), 250.0);
  const std::string md = FramePairSummaryMarkdown({s});
  EXPECT_NE(md.find("| 50.0 | 4 | 2 / **2** / 1 / 1 |"), std::string::npos) << md;
}

TEST(EvalSummary, MatchConfusionUsesRegisteredAndSkipsConsecutivePairs) {
  const Transform gt = Pose(30, 0.5, -0.2, 0.1);
  const PairTask a = MatchTask("3DMatch", 0, 2, gt);  // registered, valid
  const PairTask b = MatchTask("3DMatch", 0, 3, gt);  // not registered, valid -> WRONG
  const PairTask c = MatchTask("3DMatch", 0, 4, gt);  // not registered, invalid
  const PairTask d = MatchTask("3DMatch", 0, 1, gt);  // consecutive: not counted
  const Transform far = gt * Pose(0, 0.5, 0, 0);
  MethodOutput invalid = Output(far, {});
  invalid.valid = false;
  invalid.path = "image";
  const std::vector<PairRecord> records = {
      ScorePair(a, "m", Output(gt, {}), gt, 10), ScorePair(b, "m", Output(far, {}), gt, 20),
      ScorePair(c, "m", invalid, gt, 30), ScorePair(d, "m", Output(far, {}), gt, 40)};
  const MatchBenchmarkSummary s = SummarizeMatch({a, b, c, d}, records).at(0);
  EXPECT_EQ(s.verdicts.valid_right, 1);
  EXPECT_EQ(s.verdicts.valid_wrong, 1);
  EXPECT_EQ(s.verdicts.invalid_right, 0);
  EXPECT_EQ(s.verdicts.invalid_wrong, 1);
  EXPECT_DOUBLE_EQ(s.object_path_share, 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(s.median_time_ms, 25.0);
  EXPECT_EQ(ToJson(s)["valid_wrong"], 1);
}

TEST(EvalRecords, JsonRoundTripIsExact) {
  const Transform gt = Pose(33, 0.123456789, -1.5, 2.25);
  const PairTask t = MatchTask("3DMatch", 3, 7, gt);
  PairRecord r = ScorePair(
      t, "zeroreg", Output(gt * Pose(1.2345, 0.01, 0, 0), Correspondences(gt, 5, 2)), gt, 12.5);
  r.reason = "because";
  const PairRecord back = PairRecordFromJson(PairRecordToJson(r), "test");
  EXPECT_EQ(PairRecordToJson(back), PairRecordToJson(r));
  EXPECT_EQ(back.key, "3DMatch/scene 3 7");
  EXPECT_EQ(back.T_est, r.T_est);
  EXPECT_EQ(*back.recall_error, *r.recall_error);
  EXPECT_THROW(PairRecordFromJson(nlohmann::json{{"key", "x"}}, "line 3"), InputError);
}

// The object measures of a record: matches, centroids within 0.3 m, and the surface measure only
// when the method gave object surfaces (ScorePair), through JSON and back.
TEST(EvalRecords, ObjectMatchMeasuresAreScoredAndRoundTrip) {
  const Transform gt = Pose(10, 0.5, 0, 0);
  const PairTask t = MatchTask("3DMatch", 3, 7, gt);
  MethodOutput out = Output(gt, {});
  // Two objects per scan, each a 0.2 m patch; matched 0-0 (right) and 1-1 (1 m off: wrong).
  const auto patch = [](const Eigen::Vector3d& c) {
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) p.push_back(c + Eigen::Vector3d(0.02 * i, 0.02 * j, 0));
    return p;
  };
  const Eigen::Vector3d a(0, 0, 2), b(1, 0, 2);
  const auto move = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
    return (gt * p.homogeneous()).head<3>();
  };
  out.source_object_centroids = {a, b};
  out.target_object_centroids = {move(a), move(b) + Eigen::Vector3d(0, 1, 0)};
  out.object_matches = {{0, 0}, {1, 1}};
  PairRecord without = ScorePair(t, "zeroreg", out, gt, 1.0);
  EXPECT_EQ(without.object_matches, 2);
  EXPECT_EQ(without.object_matches_correct, 1);
  EXPECT_EQ(without.object_matches_same_surface, -1);  // no surfaces given
  EXPECT_FALSE(PairRecordToJson(without)["objects"].contains("same_surface"));
  out.source_object_surfaces = {patch(a), patch(b)};
  std::vector<Eigen::Vector3d> moved_a, moved_b;
  for (const Eigen::Vector3d& p : patch(a)) moved_a.push_back(move(p));
  for (const Eigen::Vector3d& p : patch(b)) moved_b.push_back(move(p) + Eigen::Vector3d(0, 1, 0));
  out.target_object_surfaces = {moved_a, moved_b};
  const PairRecord with = ScorePair(t, "zeroreg", out, gt, 1.0);
  EXPECT_EQ(with.object_matches_same_surface, 1);
  const PairRecord back = PairRecordFromJson(PairRecordToJson(with), "test");
  EXPECT_EQ(back.object_matches_same_surface, 1);
  EXPECT_EQ(PairRecordToJson(back), PairRecordToJson(with));
}

// The matchable pairs (the ceiling of any matcher) are a maximum one-to-one matching, not a greedy
// one: source 0 may go to target 0 or 1, source 1 only to target 0, so only re-seating source 0 on
// target 1 gives both.
TEST(EvalRecords, MatchableObjectPairsAreAMaximumOneToOneMatching) {
  EXPECT_EQ(MaximumBipartiteMatching({{true, true}, {true, false}}, 2), 2);
  EXPECT_EQ(MaximumBipartiteMatching({{true, false}, {true, false}}, 2), 1);
  EXPECT_EQ(MaximumBipartiteMatching({}, 3), 0);
  EXPECT_EQ(MaximumBipartiteMatching({{false, false, false}}, 3), 0);
  const std::vector<std::string> source{"cup", "cup", "chair"}, target{"cup", "chair", "chair"};
  const MatchableObjects objects{source, target};
  // Every pair "right": labels allow cup-cup, chair-chair twice over one source chair.
  EXPECT_EQ(CountMatchableObjectPairs(objects, [](int, int) { return true; }), 2);
  // Only differently labelled pairs right: none can be matched under the label rule.
  EXPECT_EQ(
      CountMatchableObjectPairs(objects, [&](int s, int t) { return source[s] != target[t]; }), 0);
}

// ScorePair counts the matchable pairs from the method's labels and centroids (and surfaces),
// and leaves them out (-1, not in the JSON) when the method gave no labels.
TEST(EvalRecords, MatchablePairsAreScoredFromLabelsAndRoundTrip) {
  const Transform gt = Pose(10, 0.5, 0, 0);
  const PairTask t = MatchTask("3DMatch", 3, 7, gt);
  MethodOutput out = Output(gt, {});
  const auto move = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
    return (gt * p.homogeneous()).head<3>();
  };
  const Eigen::Vector3d a(0, 0, 2), b(1, 0, 2), c(0, 1, 2);
  out.source_object_centroids = {a, b, c};
  // Target: a where it should be, b 1 m off, c in place but under another label.
  out.target_object_centroids = {move(a), move(b) + Eigen::Vector3d(0, 1, 0), move(c)};
  out.object_matches = {{1, 1}};  // a wrong match
  const PairRecord without = ScorePair(t, "zeroreg", out, gt, 1.0);
  EXPECT_EQ(without.object_pairs_matchable, -1);
  EXPECT_FALSE(PairRecordToJson(without)["objects"].contains("matchable"));
  out.source_object_labels = {"cup", "cup", "chair"};
  out.target_object_labels = {"cup", "cup", "table"};
  const PairRecord with = ScorePair(t, "zeroreg", out, gt, 1.0);
  EXPECT_EQ(with.object_matches_correct, 0);
  EXPECT_EQ(with.object_pairs_matchable, 1);                // a-a only
  EXPECT_EQ(with.object_pairs_matchable_same_surface, -1);  // no surfaces
  const PairRecord back = PairRecordFromJson(PairRecordToJson(with), "test");
  EXPECT_EQ(back.object_pairs_matchable, 1);
  EXPECT_EQ(PairRecordToJson(back), PairRecordToJson(with));
}

TEST(EvalRecords, EstLogIsWrittenInGtOrderAndScoresTheSameWhenReadBack) {
  const std::string dir = TempDir("estlog");
  const Transform gt1 = Pose(20, 0.3, 0.1, -0.2), gt2 = Pose(-40, 1.0, 0.5, 0.0);
  const std::vector<PairTask> tasks = {MatchTask("3DMatch", 0, 2, gt1),
                                       MatchTask("3DMatch", 1, 5, gt2),
                                       MatchTask("3DLoMatch", 0, 9, gt2)};
  // Estimates with many digits: est.log keeps 9 significant digits, the records use exactly
  // those (RoundLikeLogFile), so a scorer reading est.log decides every pair as we do.
  const Transform e1 = gt1 * Pose(1.0 / 3.0, 1.0 / 7.0, 0, 0), e2 = gt2 * Pose(M_PI, 0.0, 0, 0);
  std::vector<PairRecord> records = {ScorePair(tasks[1], "m", Output(e2, {}), gt2, 0),
                                     ScorePair(tasks[0], "m", Output(e1, {}), gt1, 0)};
  const auto paths = WriteEstLogs(dir, tasks, records);
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0], dir + "/3DMatch/scene/est.log");
  const std::vector<LogEntry> log = ReadLogFile(paths[0]);
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].i, 0);  // gt order, not record order
  EXPECT_EQ(log[0].j, 2);
  EXPECT_EQ(log[0].n, 60);
  EXPECT_EQ(log[1].i, 1);
  EXPECT_EQ(log[1].j, 5);
  EXPECT_EQ(log[0].T_i_j, records[1].T_est);  // bit-identical after the round trip
  EXPECT_EQ(log[1].T_i_j, records[0].T_est);
  EXPECT_TRUE(ReadLogFile(paths[1]).empty());  // no finished 3DLoMatch pair
  fs::remove_all(dir);
}

TEST(EvalProtocols, ThreeDMatchTasksOfRedkitchenFragments0To19) {
  const std::string gt = testing::SharedDir() + "/data/3dmatch-gt";
  std::vector<int> available;
  for (int k = 0; k < 20; ++k) available.push_back(k);
  const auto match = ThreeDMatchTasks(gt, "3DMatch", "7-scenes-redkitchen", available);
  const auto lo = ThreeDMatchTasks(gt, "3DLoMatch", "7-scenes-redkitchen", available);
  // The staged data's MANIFEST: 122 + 42 pairs, 103 + 42 without consecutive ones.
  EXPECT_EQ(match.size(), 122u);
  EXPECT_EQ(lo.size(), 42u);
  auto evaluated = [](const std::vector<PairTask>& v) {
    return std::count_if(v.begin(), v.end(), [](const PairTask& t) { return !t.consecutive; });
  };
  EXPECT_EQ(evaluated(match), 103);
  EXPECT_EQ(evaluated(lo), 42);
  EXPECT_EQ(match[0].Key(), "3DMatch/7-scenes-redkitchen 0 1");
  EXPECT_EQ(match[0].log_n, 60);
  // gt.log "0 2" is T_0_2 = inv(P_0) P_100: maps fragment 2 (source) into fragment 0 (target).
  const Transform P0 = ReadPoseFile(testing::RedkitchenDir() + "/frames/frame-000000.pose.txt");
  const Transform P100 = ReadPoseFile(testing::RedkitchenDir() + "/frames/frame-000100.pose.txt");
  ASSERT_EQ(match[1].source_id, 2);
  EXPECT_LT((*match[1].T_target_source_gt - P0.inverse() * P100).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(ThreeDMatchTasks(gt, "3DMatch", "no-such-scene", available), InputError);
}

TEST(EvalProtocols, FramePairsAndAvailableFragments) {
  std::vector<int> frames;
  for (int k = 0; k < 1000; ++k) frames.push_back(k);
  EXPECT_EQ(FramePairTasks(frames, 20, 10, 0, "d", "s").size(), 98u);
  const auto g60 = FramePairTasks(frames, 60, 10, 0, "d", "s");
  ASSERT_EQ(g60.size(), 94u);
  EXPECT_EQ(g60.back().target_id, 930);
  EXPECT_EQ(g60.back().source_id, 990);
  EXPECT_EQ(g60.back().source_ref, "d@990");
  EXPECT_EQ(g60.back().benchmark, "frames-g60");
  EXPECT_THROW(FramePairTasks(frames, 0, 10, 0, "d", "s"), InputError);

  EXPECT_EQ(AvailableFragments(frames, 50).size(), 20u);
  frames.erase(frames.begin() + 120);  // frame 120 missing: fragment 2 incomplete
  const auto available = AvailableFragments(frames, 50);
  EXPECT_EQ(available.size(), 19u);
  EXPECT_EQ(std::count(available.begin(), available.end(), 2), 0);
}

TEST(EvalProtocols, ShardsPartitionThePairsExactlyOnce) {
  std::vector<int> frames;
  for (int k = 0; k < 1000; ++k) frames.push_back(k);
  const auto tasks = FramePairTasks(frames, 20, 10, 0, "d", "s");
  for (int n : {1, 2, 3, 7, 200}) {
    std::map<std::string, int> seen;
    for (int i = 0; i < n; ++i) {
      for (const PairTask& t :
           ApplyShard(tasks, ParseShard(std::to_string(i) + "/" + std::to_string(n)))) {
        ++seen[t.Key()];
      }
    }
    EXPECT_EQ(seen.size(), tasks.size()) << n << " shards";
    for (const auto& [key, count] : seen) EXPECT_EQ(count, 1) << key << " with " << n << " shards";
  }
  EXPECT_THROW(ParseShard("3/3"), InputError);
  EXPECT_THROW(ParseShard("-1/3"), InputError);
  EXPECT_THROW(ParseShard("1"), InputError);
  EXPECT_THROW(ParseShard("1/2x"), InputError);
}

TEST(EvalProtocols, PairsFileSelectsAndRejectsUnknownPairs) {
  const std::string dir = TempDir("pairsfile");
  const std::string path = dir + "/pairs.txt";
  std::ofstream(path) << "# target source\n0 20\n\n40 60\n";
  std::vector<int> frames;
  for (int k = 0; k < 100; ++k) frames.push_back(k);
  const auto tasks = FramePairTasks(frames, 20, 10, 0, "d", "s");
  const auto kept = FilterPairs(tasks, ReadPairsFile(path), path);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[1].target_id, 40);
  EXPECT_THROW(FilterPairs(tasks, {{0, 21}}, path), InputError);
  std::ofstream(path) << "0 20 7\n";
  EXPECT_THROW(ReadPairsFile(path), InputError);
  EXPECT_THROW(ReadPairsFile(dir + "/missing.txt"), InputError);
  fs::remove_all(dir);
}

TEST(EvalFragments, CacheFolderNamesTheNonDefaultFusionSettings) {
  FragmentSource f;
  f.cache_dir = "c";
  f.scene = "s";
  EXPECT_EQ(f.Dir(7), "c/s/fragment-7");  // the default: 3 views, 1 cm voxel
  f.fuse.num_views = 1;
  EXPECT_EQ(f.ScanJson(0), "c/s/views-1/fragment-0/scan.json");
  f.fuse.voxel_length_m = 0.04;
  EXPECT_EQ(f.Dir(0), "c/s/views-1-voxel-40mm/fragment-0");
  // A depth scale given on the command line: its fragments do not evict the layout's.
  f = FragmentSource();
  f.cache_dir = "c";
  f.scene = "s";
  f.depth_scale = 5000;
  EXPECT_EQ(f.Dir(2), "c/s/depth-scale-5000/fragment-2");
}

}  // namespace
}  // namespace zeroreg
