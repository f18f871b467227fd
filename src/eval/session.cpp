#include "eval/session.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "eval/summary.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kFormatVersion = 1;

void WriteText(const std::string& path, const std::string& text) {
  detail::WriteFileAtomically(path, text);
}

std::string DumpForFile(const json& j) { return detail::DumpJson(j, 2) + "\n"; }

}  // namespace

OutDirLock::OutDirLock(const std::string& out_dir) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw MakeInputError(out_dir, "cannot create the results folder (" + ec.message() + ")");
  const std::string path = (fs::path(out_dir) / ".lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw MakeInputError(
        out_dir, "cannot create the lock file .lock (" + std::string(std::strerror(errno)) + ")");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw MakeInputError(out_dir,
                         "another `zeroreg eval` is writing into this results folder; "
                         "wait for it to finish or use another --out");
  }
}

OutDirLock::~OutDirLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

OutDirLock::OutDirLock(OutDirLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

json RunInfoToJson(const RunInfo& info) {
  json tasks = json::array();
  for (const PairTask& t : info.tasks) tasks.push_back(PairTaskToJson(t));
  return {{"format_version", kFormatVersion}, {"zeroreg_version", ZEROREG_VERSION},
          {"protocol", info.protocol},        {"method", info.method},
          {"settings", info.settings},        {"shard", info.shard},
          {"command", info.command},          {"pairs", tasks}};
}

RunInfo RunInfoFromJson(const json& j, const std::string& where) {
  if (!j.is_object() || j.value("format_version", 0) != kFormatVersion) {
    throw MakeInputError(where, "not a run.json of this zeroreg version (format_version " +
                                    std::to_string(kFormatVersion) + " expected)");
  }
  RunInfo info;
  try {
    info.protocol = j.at("protocol").get<std::string>();
    info.method = j.at("method").get<std::string>();
    info.settings = j.at("settings");
    info.shard = j.at("shard").get<std::string>();
    info.command = j.value("command", "");
    for (const json& t : j.at("pairs")) info.tasks.push_back(PairTaskFromJson(t, where));
  } catch (const json::exception& e) {
    throw MakeInputError(where, std::string("malformed run.json: ") + e.what());
  }
  return info;
}

namespace {

// The settings that decide a pair's result: the pipeline's `threads` does not (every result is
// bit-identical for any thread count:
// PreparedScan.OneThreadAndTwoThreadsGiveTheSameTransformBitForBit,
// Icp.ThreadCountDoesNotChangeOneBitAndPreparedGeometryIsReusable), and `zeroreg eval` sets it from
// --jobs, so a folder may be resumed or merged with another --jobs or `threads`.
json ResultSettings(const json& settings) {
  json out = settings;
  if (out.contains("pipeline") && out["pipeline"].is_object()) out["pipeline"].erase("threads");
  return out;
}

}  // namespace

RunInfo ReadRunInfo(const std::string& out_dir) {
  const std::string path = (fs::path(out_dir) / "run.json").string();
  return RunInfoFromJson(detail::ReadJsonFile(path, "run.json of a `zeroreg eval` results folder"),
                         path);
}

OutDirLock PrepareOutDir(const std::string& out_dir, const RunInfo& info) {
  OutDirLock lock(out_dir);
  const fs::path path = fs::path(out_dir) / "run.json";
  if (fs::exists(path)) {
    const RunInfo old = ReadRunInfo(out_dir);
    auto differs = [&](const char* what) {
      return MakeInputError(out_dir, std::string("holds results of a run with another ") + what +
                                         "; resuming would mix them. Use another --out, or "
                                         "delete the folder to start over");
    };
    if (old.protocol != info.protocol) throw differs("protocol");
    if (old.method != info.method) throw differs("method");
    // Compared as written: a path that is not UTF-8 was stored with U+FFFD.
    if (ResultSettings(old.settings) !=
        ResultSettings(json::parse(detail::DumpJson(info.settings)))) {
      throw differs("config or data settings");
    }
  }
  WriteText(path.string(), DumpForFile(RunInfoToJson(info)));
  return lock;
}

EvalSummary WriteSummary(const std::string& out_dir, const RunInfo& info,
                         const std::vector<PairTask>& tasks,
                         const std::vector<PairRecord>& records) {
  EvalSummary s;
  s.json = {{"protocol", info.protocol},
            {"method", info.method},
            {"shard", info.shard},
            {"command", info.command},
            {"settings", info.settings}};
  json benchmarks = json::array();
  std::string table;
  if (info.protocol == "3dmatch") {
    const auto summaries = SummarizeMatch(tasks, records);
    for (const auto& b : summaries) benchmarks.push_back(ToJson(b));
    table = MatchSummaryMarkdown(summaries);
    json logs = json::array();
    for (const std::string& p : WriteEstLogs(out_dir, tasks, records)) {
      logs.push_back(fs::relative(p, out_dir).string());
    }
    s.json["est_logs"] = logs;
  } else {
    const auto summaries = SummarizeFramePairs(tasks, records);
    for (const auto& b : summaries) benchmarks.push_back(ToJson(b));
    table = FramePairSummaryMarkdown(summaries);
    if (info.settings.contains("list")) {  // eval pairs --list: est.log beside the summary
      WriteListEstLog((fs::path(out_dir) / "est.log").string(), tasks, records);
      s.json["est_logs"] = json::array({"est.log"});
    }
  }
  s.json["benchmarks"] = benchmarks;
  s.markdown = "# zeroreg eval " + info.protocol + " — method `" + info.method + "`, shard " +
               info.shard + "\n\n" + table + "\n" + "Command: `" + info.command + "`\n";
  WriteText((fs::path(out_dir) / "summary.json").string(), DumpForFile(s.json));
  WriteText((fs::path(out_dir) / "summary.md").string(), s.markdown);
  return s;
}

namespace {

// `eval merge --out` writes run.json, pairs.jsonl and the summary: over a folder holding another
// run's results it would replace them (a complete run by a partial merge). Allowed: a new or empty
// folder, or an earlier merge of the same run (made again when more shards have finished).
void RefuseOtherResults(const std::string& out_dir, const RunInfo& merged) {
  const fs::path dir(out_dir);
  std::error_code ec;
  bool holds_results = false;
  for (const char* name : {"run.json", "pairs.jsonl", "summary.json", "summary.md"}) {
    holds_results = holds_results || fs::exists(fs::symlink_status(dir / name, ec));
  }
  if (!holds_results) return;
  if (fs::exists(dir / "run.json", ec)) {
    const RunInfo previous = ReadRunInfo(out_dir);
    if (previous.shard == "merged" && previous.protocol == merged.protocol &&
        previous.method == merged.method &&
        ResultSettings(previous.settings) == ResultSettings(merged.settings) &&
        RunInfoToJson(previous)["pairs"] == RunInfoToJson(merged)["pairs"]) {
      return;
    }
  }
  throw MakeInputError("--out " + out_dir,
                       "holds the results of another run (run.json, pairs.jsonl or a summary), "
                       "which the merge would replace; expected a new or empty folder, or an "
                       "earlier merge of the same shards");
}

}  // namespace

EvalSummary MergeRuns(const std::vector<std::string>& dirs, const std::string& out_dir,
                      int* missing) {
  if (dirs.empty()) throw MakeInputError("zeroreg eval merge", "no results folders given");
  RunInfo merged;
  std::map<std::string, PairRecord> by_key;
  for (size_t d = 0; d < dirs.size(); ++d) {
    const RunInfo info = ReadRunInfo(dirs[d]);
    if (d == 0) {
      merged = info;
    } else {
      auto differs = [&](const char* what) {
        return MakeInputError(dirs[d], std::string("has another ") + what + " than " + dirs[0] +
                                           "; only shards of one run can be merged");
      };
      if (info.protocol != merged.protocol) throw differs("protocol");
      if (info.method != merged.method) throw differs("method");
      if (ResultSettings(info.settings) != ResultSettings(merged.settings)) {
        throw differs("config or data settings");
      }
      if (RunInfoToJson(info)["pairs"] != RunInfoToJson(merged)["pairs"]) {
        throw differs("pair selection (--pairs / --limit)");
      }
    }
    const std::string jsonl = (fs::path(dirs[d]) / "pairs.jsonl").string();
    for (PairRecord& r : ReadPairsJsonl(jsonl)) {
      if (!r.error.empty()) continue;
      by_key.emplace(r.key, std::move(r));  // the first folder holding a pair wins
    }
  }
  std::vector<PairRecord> records;
  int absent = 0;
  for (const PairTask& t : merged.tasks) {
    const auto it = by_key.find(t.Key());
    if (it == by_key.end()) {
      ++absent;
    } else {
      records.push_back(it->second);
    }
  }
  if (missing) *missing = absent;
  RefuseOtherResults(out_dir, merged);
  merged.shard = "merged";
  merged.command = "zeroreg eval merge";
  for (const std::string& d : dirs) merged.command += " " + d;
  merged.command += " --out " + out_dir;
  const OutDirLock lock(out_dir);
  const fs::path run_json = fs::path(out_dir) / "run.json";
  WriteText(run_json.string(), DumpForFile(RunInfoToJson(merged)));
  WritePairsJsonl((fs::path(out_dir) / "pairs.jsonl").string(), records);
  return WriteSummary(out_dir, merged, merged.tasks, records);
}

}  // namespace zeroreg
