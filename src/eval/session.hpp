// The results folder of an evaluation run and the merge of shard folders.
//
//   <out>/run.json       protocol, method, settings (config, data, fusion), the pair selection
//                        before --shard, the shard, the command line
//   <out>/pairs.jsonl    one line per finished pair (runner.hpp)
//   <out>/summary.json   aggregate metrics (summary.hpp), plus run.json's identity fields
//   <out>/summary.md     the same as a markdown table
//   <out>/<benchmark>/<scene>/est.log   3DMatch protocol: the estimates in the standard format
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/records.hpp"

namespace zeroreg {

struct RunInfo {
  std::string protocol;  // "3dmatch" or "pairs"
  std::string method;    // "zeroreg", "image" or "fpfh"
  // Everything that decides a pair's result (method config, data, fusion settings). A folder is
  // resumed, and shard folders are merged, only when it is identical but for the pipeline's
  // `threads` (recorded, but no result depends on it).
  nlohmann::json settings = nlohmann::json::object();
  std::vector<PairTask> tasks;  // the selection before --shard
  std::string shard = "0/1";    // "i/N", or "merged"
  std::string command;          // for the record
};
nlohmann::json RunInfoToJson(const RunInfo& info);
RunInfo RunInfoFromJson(const nlohmann::json& json, const std::string& where);
RunInfo ReadRunInfo(const std::string& out_dir);  // <out>/run.json, InputError if absent/bad

// An exclusive lock on a results folder (flock on <out>/.lock), held while the object lives: two
// runs writing the same folder would evaluate and append every pair twice. The lock goes away
// with the process, so a killed run leaves no stale lock behind.
class OutDirLock {
 public:
  // Creates `out_dir` if needed; throws InputError naming it if another process holds the lock.
  explicit OutDirLock(const std::string& out_dir);
  ~OutDirLock();
  OutDirLock(OutDirLock&& other) noexcept;
  OutDirLock(const OutDirLock&) = delete;
  OutDirLock& operator=(const OutDirLock&) = delete;
  OutDirLock& operator=(OutDirLock&&) = delete;

 private:
  int fd_ = -1;
};

// Locks and creates `out_dir` and writes run.json. If the folder already holds a run.json with
// another protocol, method or settings, throws InputError (resuming would mix two methods'
// results). Keep the returned lock for as long as the run writes into the folder.
[[nodiscard]] OutDirLock PrepareOutDir(const std::string& out_dir, const RunInfo& info);

struct EvalSummary {
  nlohmann::json json;   // what summary.json holds
  std::string markdown;  // what summary.md holds
};
// Summarises `records` over `tasks` (a shard's tasks, or all) and writes summary.json,
// summary.md and, for the 3DMatch protocol, the est.log files.
EvalSummary WriteSummary(const std::string& out_dir, const RunInfo& info,
                         const std::vector<PairTask>& tasks,
                         const std::vector<PairRecord>& records);

// Merges shard folders: all must have the same protocol, method, settings and selection. Writes
// `out_dir`/pairs.jsonl (selection order), run.json (shard "merged") and the summary. Pairs found
// in no folder are reported (`*missing`) and count as in WriteSummary (failures for the recall).
// `out_dir` must be new, empty or an earlier merge of the same run: a folder holding another run's
// results is refused (InputError naming it), never replaced.
EvalSummary MergeRuns(const std::vector<std::string>& dirs, const std::string& out_dir,
                      int* missing = nullptr);

}  // namespace zeroreg
