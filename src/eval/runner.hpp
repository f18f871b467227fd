// The resumable, multi-threaded pair runner behind `zeroreg eval`.
//
// Every finished pair is appended to `<out>/pairs.jsonl` as one JSON line and flushed at once, so
// a run that is killed loses at most the pairs in flight; a restart skips every pair already
// there. With --jobs N, N threads each own one method instance (a Pipeline is not shared) and
// take pairs from a common queue; every pair's result depends on its inputs and seed only, so the
// records are those of --jobs 1. While several jobs run, pairs.jsonl grows in finishing order; when
// they are done it is rewritten (atomically) in task order, as summaries and est.log are, if it is
// not in that order already (also after a retried error or a resumed run).
#pragma once

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "eval/methods.hpp"
#include "eval/prior.hpp"
#include "eval/records.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

// Loads the scans a task refers to; safe to call from several threads. "DIR@N" refs read frame N
// of the dataset in DIR, opened once per DIR; any other ref goes to LoadScan (scan.json, ...).
class ScanLoader {
 public:
  explicit ScanLoader(DatasetOptions options = {}) : options_(options) {}
  virtual ~ScanLoader() = default;
  virtual Scan Load(const std::string& ref) const;

 private:
  DatasetOptions options_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::shared_ptr<const Dataset>> datasets_;
};

// A one-line progress bar with rate and ETA on a terminal; elsewhere (a log file under nohup or a
// scheduler) one plain line every 10% or 60 s. Thread-safe.
class ProgressBar {
 public:
  ProgressBar(std::string label, int total, bool enabled, std::FILE* out = stderr);
  void Advance();  // one more item done
  void Finish();   // final line (idempotent)

 private:
  void Draw(bool final);
  std::string label_;
  int total_, done_ = 0;
  bool enabled_, tty_, finished_ = false;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_, last_line_;
  int last_decile_ = 0, last_printed_ = -1;
  std::mutex mutex_;
};
// "1h02m", "3m05s", "42s".
std::string FormatDuration(double seconds);

struct RunOptions {
  int jobs = 1;
  bool progress = true;
  std::string label = "pairs";
  // Register every pair with a motion prior this far from its ground truth (PriorOffTheTruth,
  // drawn with `seed` and the pair's key); only for methods that take one (TakesMotionPrior).
  std::optional<PriorError> prior;
  std::uint64_t seed = 0;
};

struct RunStats {
  int reused = 0;  // already in pairs.jsonl
  int ran = 0;     // evaluated by this call
  int errors = 0;  // of those, pairs that threw (recorded with "error", re-run on resume)
};

// Keys of the tasks that `jsonl_path` already holds an error-free record for.
std::vector<std::string> DoneKeys(const std::string& jsonl_path);

// Evaluates every task of `tasks` without an error-free record in `jsonl_path` and appends its
// record there. Returns the records of all of `tasks` now in the file, in task order.
std::vector<PairRecord> RunPairs(const std::vector<PairTask>& tasks, const std::string& method,
                                 const MethodFactory& factory, const ScanLoader& loader,
                                 const std::string& jsonl_path, const RunOptions& options,
                                 RunStats* stats = nullptr);

}  // namespace zeroreg
