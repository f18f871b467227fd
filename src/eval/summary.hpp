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
// Frame pairs (the UR&R ScanNet protocol, paper Table 3): over finished pairs, whatever the
//   method's verdict, the fraction with RE < 5/10/45 deg and TE < 5/10/25 cm, and mean / median.
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
  std::map<std::string, int> paths;  // finished pairs per correspondence path
};

struct FramePairSummary {
  std::string benchmark;
  int num_pairs = 0, num_done = 0, num_valid = 0;
  // Fractions of finished pairs below each threshold (strictly).
  std::vector<double> rotation_thresholds_deg{5, 10, 45};
  std::vector<double> translation_thresholds_cm{5, 10, 25};
  std::vector<double> rotation_accuracy, translation_accuracy;
  Stats rotation_error_deg, translation_error_cm;
  double mean_time_s = 0;
  std::map<std::string, int> paths;  // finished pairs per correspondence path
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

// Writes `<dir>/<benchmark>/<scene>/est.log` for every 3DMatch-style benchmark/scene of `tasks`,
// holding the finished pairs in task (gt.log) order. Returns the paths written.
std::vector<std::string> WriteEstLogs(const std::string& dir, const std::vector<PairTask>& tasks,
                                      const std::vector<PairRecord>& records);

}  // namespace zeroreg
