#include "eval/summary.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::map<std::string, const PairRecord*> IndexDone(const std::vector<PairRecord>& records) {
  std::map<std::string, const PairRecord*> done;
  for (const PairRecord& r : records) {
    if (r.error.empty()) done[r.key] = &r;
  }
  return done;
}

// Benchmarks (or scenes) in first-seen order.
template <typename Getter>
std::vector<std::string> Distinct(const std::vector<PairTask>& tasks, Getter get) {
  std::vector<std::string> names;
  for (const PairTask& t : tasks) {
    if (std::find(names.begin(), names.end(), get(t)) == names.end()) names.push_back(get(t));
  }
  return names;
}

double Mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / v.size();
}

json StatsJson(const Stats& s) {
  return {{"mean", s.mean}, {"median", s.median}, {"count", s.count}};
}

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}
std::string Percent(double fraction) { return Format("%.1f", 100.0 * fraction); }

// "object 90, image-fallback 32": how many finished pairs each correspondence path produced.
std::string PathsText(const std::map<std::string, int>& paths) {
  std::string text;
  for (const auto& [path, count] : paths) {
    text += (text.empty() ? "" : ", ") + (path.empty() ? std::string("?") : path) + " " +
            std::to_string(count);
  }
  return text;
}

double ObjectShare(const std::map<std::string, int>& paths, int done) {
  const auto it = paths.find("object");
  return done > 0 && it != paths.end() ? static_cast<double>(it->second) / done : 0.0;
}

// "12 / **1** / 3 / 4": valid-right / valid-WRONG (bold when > 0) / invalid-right / invalid-wrong.
std::string VerdictsText(const VerdictCounts& v) {
  const std::string wrong = v.valid_wrong > 0 ? "**" + std::to_string(v.valid_wrong) + "**"
                                              : std::to_string(v.valid_wrong);
  return std::to_string(v.valid_right) + " / " + wrong + " / " + std::to_string(v.invalid_right) +
         " / " + std::to_string(v.invalid_wrong);
}

}  // namespace

bool FramePairSuccess(const PairRecord& r) {
  return r.rotation_error_deg < kSuccessRotationDeg && r.translation_error_m < kSuccessTranslationM;
}

void VerdictCounts::Add(bool valid, bool right) {
  if (valid) {
    ++(right ? valid_right : valid_wrong);
  } else {
    ++(right ? invalid_right : invalid_wrong);
  }
}

Stats ComputeStats(std::vector<double> values) {
  Stats s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) return s;
  s.mean = Mean(values);
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  s.median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return s;
}

std::vector<MatchBenchmarkSummary> SummarizeMatch(const std::vector<PairTask>& tasks,
                                                  const std::vector<PairRecord>& records) {
  const auto done = IndexDone(records);
  std::vector<MatchBenchmarkSummary> out;
  for (const std::string& benchmark :
       Distinct(tasks, [](const PairTask& t) { return t.benchmark; })) {
    MatchBenchmarkSummary s;
    s.benchmark = benchmark;
    std::vector<PairTask> bench_tasks;
    for (const PairTask& t : tasks) {
      if (t.benchmark == benchmark) bench_tasks.push_back(t);
    }
    std::vector<double> scene_rr, scene_ir, scene_fmr, rot, trans_cm, times_ms;
    double total_time_ms = 0;
    for (const std::string& scene :
         Distinct(bench_tasks, [](const PairTask& t) { return t.scene; })) {
      int evaluated = 0, registered = 0, finished = 0, matched = 0;
      double ir_sum = 0;
      for (const PairTask& t : bench_tasks) {
        if (t.scene != scene) continue;
        ++s.num_pairs;
        if (!t.consecutive) ++evaluated;
        const auto it = done.find(t.Key());
        if (it == done.end()) continue;
        const PairRecord& r = *it->second;
        ++finished;
        ++s.paths[r.path];
        total_time_ms += r.time_ms;
        times_ms.push_back(r.time_ms);
        if (r.valid) ++s.num_valid;
        if (!t.consecutive) s.verdicts.Add(r.valid, r.registered);
        ir_sum += r.inlier_ratio;
        if (r.inlier_ratio > kFeatureMatchRecallThreshold) ++matched;
        if (!t.consecutive && r.registered) {
          ++registered;
          rot.push_back(r.rotation_error_deg);
          trans_cm.push_back(100.0 * r.translation_error_m);
        }
      }
      ++s.num_scenes;
      s.num_done += finished;
      s.num_evaluated += evaluated;
      s.num_registered += registered;
      scene_rr.push_back(evaluated > 0 ? static_cast<double>(registered) / evaluated : 0.0);
      if (finished > 0) {
        scene_ir.push_back(ir_sum / finished);
        scene_fmr.push_back(static_cast<double>(matched) / finished);
      }
    }
    s.registration_recall = Mean(scene_rr);
    s.inlier_ratio = Mean(scene_ir);
    s.feature_match_recall = Mean(scene_fmr);
    s.rotation_error_deg = ComputeStats(rot);
    s.translation_error_cm = ComputeStats(trans_cm);
    s.mean_time_s = s.num_done > 0 ? total_time_ms / 1000.0 / s.num_done : 0.0;
    s.median_time_ms = ComputeStats(times_ms).median;
    s.object_path_share = ObjectShare(s.paths, s.num_done);
    out.push_back(s);
  }
  return out;
}

std::vector<FramePairSummary> SummarizeFramePairs(const std::vector<PairTask>& tasks,
                                                  const std::vector<PairRecord>& records) {
  const auto done = IndexDone(records);
  std::vector<FramePairSummary> out;
  for (const std::string& benchmark :
       Distinct(tasks, [](const PairTask& t) { return t.benchmark; })) {
    FramePairSummary s;
    s.benchmark = benchmark;
    std::vector<double> rot, trans_cm, times_ms;
    double total_time_ms = 0;
    int successes = 0;
    for (const PairTask& t : tasks) {
      if (t.benchmark != benchmark) continue;
      ++s.num_pairs;
      const auto it = done.find(t.Key());
      if (it == done.end()) continue;
      ++s.num_done;
      ++s.paths[it->second->path];
      if (it->second->valid) ++s.num_valid;
      rot.push_back(it->second->rotation_error_deg);
      trans_cm.push_back(100.0 * it->second->translation_error_m);
      total_time_ms += it->second->time_ms;
      times_ms.push_back(it->second->time_ms);
      const bool success = FramePairSuccess(*it->second);
      if (success) ++successes;
      s.verdicts.Add(it->second->valid, success);
    }
    auto accuracy = [](const std::vector<double>& errors, double threshold) {
      if (errors.empty()) return 0.0;
      const auto below =
          std::count_if(errors.begin(), errors.end(), [&](double e) { return e < threshold; });
      return static_cast<double>(below) / errors.size();
    };
    for (double t : s.rotation_thresholds_deg) s.rotation_accuracy.push_back(accuracy(rot, t));
    for (double t : s.translation_thresholds_cm) {
      s.translation_accuracy.push_back(accuracy(trans_cm, t));
    }
    s.rotation_error_deg = ComputeStats(rot);
    s.translation_error_cm = ComputeStats(trans_cm);
    s.mean_time_s = s.num_done > 0 ? total_time_ms / 1000.0 / s.num_done : 0.0;
    s.median_time_ms = ComputeStats(times_ms).median;
    s.success = s.num_done > 0 ? static_cast<double>(successes) / s.num_done : 0.0;
    s.object_path_share = ObjectShare(s.paths, s.num_done);
    out.push_back(s);
  }
  return out;
}

// The verdict confusion of a summary, as the four keys both protocols write.
// The fields both kinds of summary end with: error statistics, time, paths and verdicts.
template <typename Summary>
void AddCommonFields(const Summary& s, json* out) {
  (*out)["rotation_error_deg"] = StatsJson(s.rotation_error_deg);
  (*out)["translation_error_cm"] = StatsJson(s.translation_error_cm);
  (*out)["mean_time_s"] = s.mean_time_s;
  (*out)["median_time_ms"] = s.median_time_ms;
  (*out)["paths"] = s.paths;
  (*out)["object_path_share"] = s.object_path_share;
  (*out)["valid_right"] = s.verdicts.valid_right;
  (*out)["valid_wrong"] = s.verdicts.valid_wrong;
  (*out)["invalid_right"] = s.verdicts.invalid_right;
  (*out)["invalid_wrong"] = s.verdicts.invalid_wrong;
}

json ToJson(const MatchBenchmarkSummary& s) {
  json out{{"benchmark", s.benchmark},
           {"scenes", s.num_scenes},
           {"pairs", s.num_pairs},
           {"done", s.num_done},
           {"missing", s.num_pairs - s.num_done},
           {"evaluated", s.num_evaluated},
           {"registered", s.num_registered},
           {"valid", s.num_valid},
           {"registration_recall", s.registration_recall},
           {"inlier_ratio", s.inlier_ratio},
           {"feature_match_recall", s.feature_match_recall}};
  AddCommonFields(s, &out);
  return out;
}

json ToJson(const FramePairSummary& s) {
  json rot_acc = json::object(), trans_acc = json::object();
  for (size_t k = 0; k < s.rotation_thresholds_deg.size(); ++k) {
    rot_acc[Format("%g", s.rotation_thresholds_deg[k])] = s.rotation_accuracy[k];
  }
  for (size_t k = 0; k < s.translation_thresholds_cm.size(); ++k) {
    trans_acc[Format("%g", s.translation_thresholds_cm[k])] = s.translation_accuracy[k];
  }
  json out{{"benchmark", s.benchmark},
           {"pairs", s.num_pairs},
           {"done", s.num_done},
           {"missing", s.num_pairs - s.num_done},
           {"valid", s.num_valid},
           {"rotation_accuracy_deg", rot_acc},
           {"translation_accuracy_cm", trans_acc},
           {"success", s.success}};
  AddCommonFields(s, &out);
  return out;
}

std::string MatchSummaryMarkdown(const std::vector<MatchBenchmarkSummary>& summaries) {
  std::ostringstream md;
  md << "| benchmark | pairs | done | evaluated (j > i+1) | registered | RR (%) | IR (%) | "
        "FMR (%) | RE mean / med (deg) | TE mean / med (cm) | valid verdicts | valid-right / "
        "valid-WRONG / invalid-right / invalid-wrong (right = registered) | time / pair (s) | "
        "median (ms) | object path (%) | paths |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const MatchBenchmarkSummary& s : summaries) {
    md << "| " << s.benchmark << " | " << s.num_pairs << " | " << s.num_done << " | "
       << s.num_evaluated << " | " << s.num_registered << " | " << Percent(s.registration_recall)
       << " | " << Percent(s.inlier_ratio) << " | " << Percent(s.feature_match_recall) << " | "
       << Format("%.2f", s.rotation_error_deg.mean) << " / "
       << Format("%.2f", s.rotation_error_deg.median) << " | "
       << Format("%.1f", s.translation_error_cm.mean) << " / "
       << Format("%.1f", s.translation_error_cm.median) << " | " << s.num_valid << " | "
       << VerdictsText(s.verdicts) << " | " << Format("%.2f", s.mean_time_s) << " | "
       << Format("%.0f", s.median_time_ms) << " | " << Percent(s.object_path_share) << " | "
       << PathsText(s.paths) << " |\n";
  }
  return md.str();
}

std::string FramePairSummaryMarkdown(const std::vector<FramePairSummary>& summaries) {
  std::ostringstream md;
  md << "| benchmark | pairs | done | RE acc 5 / 10 / 45 deg (%) | RE mean / med (deg) | "
        "TE acc 5 / 10 / 25 cm (%) | TE mean / med (cm) | success (%) | valid verdicts | "
        "valid-right / valid-WRONG / invalid-right / invalid-wrong | time / pair (s) | "
        "median (ms) | object path (%) | paths |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const FramePairSummary& s : summaries) {
    auto accuracies = [](const std::vector<double>& a) {
      std::string text;
      for (size_t k = 0; k < a.size(); ++k) text += (k ? " / " : "") + Percent(a[k]);
      return text;
    };
    md << "| " << s.benchmark << " | " << s.num_pairs << " | " << s.num_done << " | "
       << accuracies(s.rotation_accuracy) << " | " << Format("%.2f", s.rotation_error_deg.mean)
       << " / " << Format("%.2f", s.rotation_error_deg.median) << " | "
       << accuracies(s.translation_accuracy) << " | " << Format("%.1f", s.translation_error_cm.mean)
       << " / " << Format("%.1f", s.translation_error_cm.median) << " | " << Percent(s.success)
       << " | " << s.num_valid << " | " << VerdictsText(s.verdicts) << " | "
       << Format("%.2f", s.mean_time_s) << " | " << Format("%.0f", s.median_time_ms) << " | "
       << Percent(s.object_path_share) << " | " << PathsText(s.paths) << " |\n";
  }
  return md.str();
}

// The est.log entry of a finished pair: "i j n" and the estimate T_target_source = T_i_j.
LogEntry EstLogEntry(const PairTask& t, const PairRecord& r) {
  LogEntry e;
  e.i = t.target_id;
  e.j = t.source_id;
  e.n = r.log_n;
  e.T_i_j = r.T_est;
  return e;
}

void WriteListEstLog(const std::string& path, const std::vector<PairTask>& tasks,
                     const std::vector<PairRecord>& records) {
  const auto done = IndexDone(records);
  std::vector<LogEntry> entries;
  for (const PairTask& t : tasks) {
    const auto it = done.find(t.Key());
    if (it == done.end()) continue;
    entries.push_back(EstLogEntry(t, *it->second));
  }
  WriteLogFile(path, entries);
}

std::vector<std::string> WriteEstLogs(const std::string& dir, const std::vector<PairTask>& tasks,
                                      const std::vector<PairRecord>& records) {
  const auto done = IndexDone(records);
  std::map<std::pair<std::string, std::string>, std::vector<LogEntry>> logs;
  std::vector<std::pair<std::string, std::string>> order;
  for (const PairTask& t : tasks) {
    const auto group = std::make_pair(t.benchmark, t.scene);
    if (logs.find(group) == logs.end()) {
      logs[group];
      order.push_back(group);
    }
    const auto it = done.find(t.Key());
    if (it == done.end()) continue;
    logs[group].push_back(EstLogEntry(t, *it->second));
  }
  std::vector<std::string> written;
  for (const auto& group : order) {
    const fs::path folder = fs::path(dir) / group.first / group.second;
    fs::create_directories(folder);
    const std::string path = (folder / "est.log").string();
    WriteLogFile(path, logs[group]);
    written.push_back(path);
  }
  return written;
}

}  // namespace zeroreg
