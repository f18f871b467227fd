#include "eval/runner.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace fs = std::filesystem;

Scan ScanLoader::Load(const std::string& ref) const {
  const size_t at = ref.rfind('@');
  if (at != std::string::npos && at + 1 < ref.size() &&
      ref.find_first_not_of("0123456789", at + 1) == std::string::npos && at + 10 > ref.size() &&
      !fs::exists(ref)) {
    const std::string dir = ref.substr(0, at);
    std::shared_ptr<const Dataset> dataset;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto& slot = datasets_[dir];
      if (!slot) slot = std::shared_ptr<const Dataset>(OpenDataset(dir, options_));
      dataset = slot;
    }
    return ScanFromView(dataset->LoadFrame(std::stoi(ref.substr(at + 1))));
  }
  return LoadScan(ref, options_);
}

std::string FormatDuration(double seconds) {
  const long s = std::max(0L, static_cast<long>(seconds + 0.5));
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof(text), "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else if (s >= 60) {
    std::snprintf(text, sizeof(text), "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(text, sizeof(text), "%lds", s);
  }
  return text;
}

ProgressBar::ProgressBar(std::string label, int total, bool enabled, std::FILE* out)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && total > 0),
      tty_(isatty(fileno(out)) != 0),
      out_(out),
      start_(std::chrono::steady_clock::now()),
      last_line_(start_) {
  if (enabled_) Draw(false);
}

void ProgressBar::Advance() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  if (enabled_) Draw(false);
}

void ProgressBar::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!enabled_ || finished_) return;
  Draw(true);
  finished_ = true;
}

void ProgressBar::Draw(bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!tty_ && final && last_printed_ == done_) return;  // the last plain line said it all
  if (!tty_ && !final) {
    // Plain lines for logs: every 10% or every minute.
    const int decile = total_ > 0 ? done_ * 10 / total_ : 0;
    const double since = std::chrono::duration<double>(now - last_line_).count();
    if (done_ > 0 && decile == last_decile_ && since < 60.0) return;
    if (done_ == 0 && elapsed > 0) return;
    last_decile_ = decile;
    last_line_ = now;
  }
  const double rate = elapsed > 0 ? done_ / elapsed : 0.0;
  std::string eta = "?";
  if (done_ > 0 && rate > 0) eta = FormatDuration((total_ - done_) / rate);
  constexpr int kWidth = 30;
  const int filled = total_ > 0 ? kWidth * done_ / total_ : kWidth;
  std::string bar(static_cast<size_t>(filled), '=');
  if (filled < kWidth) bar += '>' + std::string(static_cast<size_t>(kWidth - filled - 1), ' ');
  char rate_text[32];
  if (rate >= 1.0 || rate == 0.0) {
    std::snprintf(rate_text, sizeof(rate_text), "%.2f/s", rate);
  } else {
    std::snprintf(rate_text, sizeof(rate_text), "%.1f s each", 1.0 / rate);
  }
  std::fprintf(out_, "%s%s [%s] %d/%d  %s  elapsed %s  ETA %s%s", tty_ ? "\r" : "", label_.c_str(),
               bar.c_str(), done_, total_, rate_text, FormatDuration(elapsed).c_str(),
               final ? "0s" : eta.c_str(), tty_ && !final ? "   " : "\n");
  std::fflush(out_);
  last_printed_ = done_;
}

std::vector<std::string> DoneKeys(const std::string& jsonl_path) {
  std::vector<std::string> keys;
  for (const PairRecord& r : ReadPairsJsonl(jsonl_path)) {
    if (r.error.empty()) keys.push_back(r.key);
  }
  return keys;
}

namespace {

PairRecord EvaluateOne(const PairTask& task, const std::string& method, PairMethod& instance,
                       const ScanLoader& loader, const RunOptions& options) {
  // Scans are read when the method asks for them (a method with prepared scans does not ask again
  // for a scan it has); the record's time is the method's, without reading.
  double load_ms = 0;
  std::map<std::string, Scan> loaded;  // read for the ground truth, handed on to the method
  const auto load = [&](const std::string& ref) -> Scan {
    const auto it = loaded.find(ref);
    if (it != loaded.end()) return it->second;
    const auto start = std::chrono::steady_clock::now();
    Scan scan = loader.Load(ref);
    load_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return scan;
  };
  Transform T_gt;
  if (task.T_target_source_gt) {
    T_gt = *task.T_target_source_gt;
  } else {
    Scan source = load(task.source_ref), target = load(task.target_ref);
    if (!source.T_world_scan_gt || !target.T_world_scan_gt) {
      throw MakeInputError(task.source_ref + " / " + task.target_ref,
                           "no ground-truth pose; the evaluation needs posed frames");
    }
    T_gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
    loaded.emplace(task.source_ref, std::move(source));
    loaded.emplace(task.target_ref, std::move(target));
    load_ms = 0;
  }
  std::optional<MotionPrior> prior;
  if (options.prior) prior = PriorOffTheTruth(T_gt, *options.prior, options.seed, task.Key());
  const auto start = std::chrono::steady_clock::now();
  const MethodOutput output = instance.RunRefs(task.source_ref, task.target_ref, load, prior);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() -
      load_ms;
  return ScorePair(task, method, output, T_gt, ms);
}

PairRecord ErrorRecord(const PairTask& task, const std::string& method, const std::string& what) {
  PairRecord r = ScorePair(task, method, MethodOutput(), Transform::Identity(), 0.0);
  r.error = what.empty() ? "unknown error" : what;
  r.reason = "error: " + r.error;
  return r;
}

// Several jobs append in finishing order, and a retried error or a run resumed after a kill adds
// its records at the end; the finished file is put in task order, so that it does not depend on
// the job count or on the run's history. Each key keeps one line, its latest record (a retry
// supersedes the error it re-ran; a line written twice counts once). Records of other tasks (an
// earlier run's larger --limit) keep their order after these.
void RewriteInTaskOrder(const std::vector<PairTask>& tasks, const std::string& jsonl_path,
                        std::vector<PairRecord>* records) {
  std::map<std::string, size_t> task_index, last_line;
  for (size_t k = 0; k < tasks.size(); ++k) task_index.emplace(tasks[k].Key(), k);
  for (size_t line = 0; line < records->size(); ++line) last_line[(*records)[line].key] = line;
  std::vector<std::pair<size_t, size_t>> order;  // (task index, line), sorted = the new order
  for (size_t line = 0; line < records->size(); ++line) {
    const std::string& key = (*records)[line].key;
    if (last_line[key] != line) continue;  // superseded by a later line
    const auto it = task_index.find(key);
    order.emplace_back(it == task_index.end() ? tasks.size() : it->second, line);
  }
  if (order.size() == records->size() && std::is_sorted(order.begin(), order.end())) return;
  std::sort(order.begin(), order.end());
  std::vector<PairRecord> sorted;
  sorted.reserve(order.size());
  for (const auto& [task, line] : order) sorted.push_back(std::move((*records)[line]));
  *records = std::move(sorted);
  WritePairsJsonl(jsonl_path, *records);
}

}  // namespace

std::vector<PairRecord> RunPairs(const std::vector<PairTask>& tasks, const std::string& method,
                                 const MethodFactory& factory, const ScanLoader& loader,
                                 const std::string& jsonl_path, const RunOptions& options,
                                 RunStats* stats) {
  RunStats local;
  bool dropped = false;
  int superseded = 0;
  std::vector<PairRecord> existing = ReadPairsJsonl(jsonl_path, &dropped, &superseded);
  if (dropped) {
    // A run was killed mid-line: rewrite the file without the partial line before appending.
    std::fprintf(stderr, "%s: dropping a truncated last line (interrupted run)\n",
                 jsonl_path.c_str());
  }
  if (superseded > 0) {
    std::fprintf(stderr, "%s: keeping one line per pair (%d lines repeated a pair)\n",
                 jsonl_path.c_str(), superseded);
  }
  if (dropped || superseded > 0) WritePairsJsonl(jsonl_path, existing);
  std::set<std::string> done;
  for (const PairRecord& r : existing) {
    if (r.error.empty()) done.insert(r.key);
  }
  std::vector<const PairTask*> todo;
  for (const PairTask& t : tasks) {
    if (done.count(t.Key())) {
      ++local.reused;
    } else {
      todo.push_back(&t);
    }
  }

  if (!todo.empty()) {
    if (!fs::path(jsonl_path).parent_path().empty()) {
      fs::create_directories(fs::path(jsonl_path).parent_path());
    }
    std::ofstream out(jsonl_path, std::ios::app);
    if (!out) throw MakeInputError(jsonl_path, "cannot open the pair results file for appending");
    std::mutex out_mutex;
    ProgressBar bar(options.label, static_cast<int>(todo.size()), options.progress);
    std::atomic<size_t> next{0};
    auto worker = [&]() {
      std::unique_ptr<PairMethod> instance;
      std::string setup_error;
      try {
        instance = factory();
      } catch (const std::exception& e) {
        setup_error = e.what();
      }
      for (size_t k = next++; k < todo.size(); k = next++) {
        const PairTask& task = *todo[k];
        PairRecord record;
        if (!instance) {
          record = ErrorRecord(task, method, "method setup failed: " + setup_error);
        } else {
          try {
            record = EvaluateOne(task, method, *instance, loader, options);
          } catch (const std::exception& e) {
            record = ErrorRecord(task, method, e.what());
          }
        }
        std::lock_guard<std::mutex> lock(out_mutex);
        if (!record.error.empty()) {
          ++local.errors;
          std::fprintf(stderr, "\npair %s failed: %s\n", record.key.c_str(), record.error.c_str());
        }
        out << detail::DumpJson(PairRecordToJson(record)) << "\n";
        out.flush();
        ++local.ran;
        existing.push_back(std::move(record));
        bar.Advance();
      }
    };
    const int jobs = std::max(1, std::min<int>(options.jobs, static_cast<int>(todo.size())));
    std::vector<std::thread> threads;
    for (int t = 1; t < jobs; ++t) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();
    bar.Finish();
    if (!out) throw MakeInputError(jsonl_path, "failed writing the pair results file");
    out.close();
    RewriteInTaskOrder(tasks, jsonl_path, &existing);
  }

  // Latest record per key, in task order.
  std::map<std::string, const PairRecord*> latest;
  for (const PairRecord& r : existing) latest[r.key] = &r;
  std::vector<PairRecord> records;
  for (const PairTask& t : tasks) {
    const auto it = latest.find(t.Key());
    if (it != latest.end()) records.push_back(*it->second);
  }
  if (stats) *stats = local;
  return records;
}

}  // namespace zeroreg
