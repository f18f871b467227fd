// Aggregate metrics of an evaluation run (DESIGN §6) and their JSON / markdown forms.
//
// 3DMatch / 3DLoMatch (per benchmark, averaged per scene, then over scenes):
//   - registration recall RR = registered / evaluated, where evaluated = the run's ground-truth
//     pairs with j > i + 1 (consecutive pairs are registered but never counted) and registered
//     means E <= 0.2^2 with E from gt.info. A pair with no result counts as not registered,
//     as in the standard scorer.
//   - inlier ratio IR = mean over finished pairs (consecutive ones included, the Predator /
//     GeoTransformer convention) of the fraction of the method's correspondences within 0.1 m
//     under the ground truth; feature-match recall FMR = fraction of those pairs with IR > 0.05.
//   - RE (deg) / TE (cm): mean and median over the registered evaluated pairs.
//   - verdict confusion over the finished evaluated pairs, right = registered.
// Frame pairs (the UR&R ScanNet protocol, paper Table 3): over finished pairs, whatever the
//   method's verdict, the fraction with RE < 5/10/45 deg and TE < 5/10/25 cm, and mean / median;
//   success = fraction with RE < 15 deg and TE < 30 cm (loop-closure style), and the verdict
//   confusion with right = success.
// Both: object_path_share = fraction of finished pairs whose path is exactly "object" (the
//   zeroreg object level), the per-path counts, and the median registration time per pair.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/records.hpp"

namespace zeroreg {

struct Stats {
  double mean = 0.0, median = 0.0;
  int count = 0;
};
Stats ComputeStats(std::vector<double> values);  // count 0 -> mean = median = 0

// Loop-closure success of a frame pair: RE < 15 deg and TE < 30 cm.
constexpr double kSuccessRotationDeg = 15.0;
constexpr double kSuccessTranslationM = 0.30;
bool FramePairSuccess(const PairRecord& record);

// The method's verdict (valid) against whether the estimate is right.
struct VerdictCounts {
  int valid_right = 0;
  int valid_wrong = 0;  // the dangerous one: a confident wrong transform
  int invalid_right = 0;
  int invalid_wrong = 0;
  void Add(bool valid, bool right);
};

struct MatchBenchmarkSummary {
  std::string benchmark;
  int num_scenes = 0;
  int num_pairs = 0;      // selected pairs, consecutive included
  int num_done = 0;       // pairs with a result
  int num_evaluated = 0;  // pairs counted in the recall (j > i + 1)
  int num_registered = 0;
  int num_valid = 0;                // the method's own verdict, over finished pairs
  double registration_recall = 0;   // fraction, averaged per scene
  double inlier_ratio = 0;          // fraction, averaged per scene
  double feature_match_recall = 0;  // fraction, averaged per scene
  Stats rotation_error_deg;         // registered evaluated pairs
  Stats translation_error_cm;
  double mean_time_s = 0;            // per finished pair
  double median_time_ms = 0;         // per finished pair
  std::map<std::string, int> paths;  // finished pairs per correspondence path
  double object_path_share = 0;      // finished pairs with path "object" / finished pairs
  VerdictCounts verdicts;            // finished evaluated pairs, right = registered
};

struct FramePairSummary {
  std::string benchmark;
  int num_pairs = 0, num_done = 0, num_valid = 0;
  // Fractions of finished pairs below each threshold (strictly).
  std::vector<double> rotation_thresholds_deg{5, 10, 45};
  std::vector<double> translation_thresholds_cm{5, 10, 25};
  std::vector<double> rotation_accuracy, translation_accuracy;
  Stats rotation_error_deg, translation_error_cm;
  double success = 0;  // fraction of finished pairs with FramePairSuccess
  double mean_time_s = 0;
  double median_time_ms = 0;
  std::map<std::string, int> paths;  // finished pairs per correspondence path
  double object_path_share = 0;      // finished pairs with path "object" / finished pairs
  VerdictCounts verdicts;            // finished pairs, right = FramePairSuccess
};

// `tasks` is the run's selection (it gives the denominators); `records` may hold more or fewer
// pairs (only those whose key is in `tasks` count). Benchmarks appear in first-seen task order.
std::vector<MatchBenchmarkSummary> SummarizeMatch(const std::vector<PairTask>& tasks,
                                                  const std::vector<PairRecord>& records);
std::vector<FramePairSummary> SummarizeFramePairs(const std::vector<PairTask>& tasks,
                                                  const std::vector<PairRecord>& records);

nlohmann::json ToJson(const MatchBenchmarkSummary& s);
nlohmann::json ToJson(const FramePairSummary& s);
// Markdown tables: one row per benchmark, columns shaped like the paper's Tables 1 and 3.
std::string MatchSummaryMarkdown(const std::vector<MatchBenchmarkSummary>& summaries);
std::string FramePairSummaryMarkdown(const std::vector<FramePairSummary>& summaries);

// Writes `path` (eval pairs --list): the finished pairs in task (pairs.txt) order, gt.log format.
void WriteListEstLog(const std::string& path, const std::vector<PairTask>& tasks,
                     const std::vector<PairRecord>& records);

// Writes `<dir>/<benchmark>/<scene>/est.log` for every 3DMatch-style benchmark/scene of `tasks`,
// holding the finished pairs in task (gt.log) order. Returns the paths written.
std::vector<std::string> WriteEstLogs(const std::string& dir, const std::vector<PairTask>& tasks,
                                      const std::vector<PairRecord>& records);

}  // namespace zeroreg
