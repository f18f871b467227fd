#include "eval/protocols.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "io/shown.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace fs = std::filesystem;

std::vector<int> AvailableFragments(const std::vector<int>& frame_ids, int frames_per_fragment) {
  std::vector<int> fragments;
  if (frames_per_fragment < 1 || frame_ids.empty()) return fragments;
  const int last = frame_ids.back();
  for (int k = 0; static_cast<long long>(k) * frames_per_fragment <= last; ++k) {
    bool complete = true;
    for (int f = k * frames_per_fragment; f < (k + 1) * frames_per_fragment && complete; ++f) {
      complete = std::binary_search(frame_ids.begin(), frame_ids.end(), f);
    }
    if (complete) fragments.push_back(k);
  }
  return fragments;
}

std::vector<PairTask> ThreeDMatchTasks(const std::string& gt_root, const std::string& benchmark,
                                       const std::string& scene,
                                       const std::vector<int>& available) {
  const fs::path folder = fs::path(gt_root) / benchmark / scene;
  const std::string log_path = (folder / "gt.log").string();
  const std::string info_path = (folder / "gt.info").string();
  if (!fs::is_regular_file(log_path)) {
    throw MakeInputError(log_path, "not found; expected --gt to hold " + benchmark + "/" + scene +
                                       "/gt.log (the 3DMatch benchmark layout)");
  }
  if (!fs::is_regular_file(info_path)) {
    throw MakeInputError(info_path, "not found; the registration recall needs gt.info");
  }
  const std::vector<LogEntry> log = ReadLogFile(log_path);
  std::map<std::pair<int, int>, InformationMatrix> info;
  for (const InfoEntry& e : ReadInfoFile(info_path)) info[{e.i, e.j}] = e.information;
  auto has = [&](int k) { return std::binary_search(available.begin(), available.end(), k); };
  std::vector<PairTask> tasks;
  for (const LogEntry& e : log) {
    if (!has(e.i) || !has(e.j)) continue;
    const auto it = info.find({e.i, e.j});
    if (it == info.end()) {
      throw MakeInputError(info_path, "has no entry for pair " + std::to_string(e.i) + " " +
                                          std::to_string(e.j) + " of " + log_path);
    }
    PairTask t;
    t.benchmark = benchmark;
    t.scene = scene;
    t.target_id = e.i;
    t.source_id = e.j;
    t.T_target_source_gt = e.T_i_j;  // gt.log "i j" maps fragment j (source) into i (target)
    t.information = it->second;
    t.log_n = e.n;
    t.consecutive = e.j == e.i + 1;
    tasks.push_back(t);
  }
  return tasks;
}

std::vector<PairTask> FramePairTasks(const std::vector<int>& frame_ids, int gap, int step,
                                     int first, const std::string& dataset_root,
                                     const std::string& scene) {
  if (gap < 1) throw MakeInputError("--gap " + std::to_string(gap), "expected at least 1");
  if (step < 1) throw MakeInputError("--step " + std::to_string(step), "expected at least 1");
  auto has = [&](int id) { return std::binary_search(frame_ids.begin(), frame_ids.end(), id); };
  std::vector<PairTask> tasks;
  if (frame_ids.empty()) return tasks;
  for (long long i = first; i + gap <= frame_ids.back(); i += step) {
    const int target = static_cast<int>(i), source = static_cast<int>(i + gap);
    if (!has(target) || !has(source)) continue;
    PairTask t;
    t.benchmark = "frames-g" + std::to_string(gap);
    t.scene = scene;
    t.target_id = target;
    t.source_id = source;
    t.target_ref = dataset_root + "@" + std::to_string(target);
    t.source_ref = dataset_root + "@" + std::to_string(source);
    tasks.push_back(t);
  }
  return tasks;
}

std::vector<std::pair<int, int>> ReadPairsFile(const std::string& path) {
  detail::RequireFile(path, "pairs file (--pairs)");  // also refuses a FIFO, which would block
  std::ifstream in(path);
  if (!in) throw MakeInputError(path, "cannot open the pairs file; expected lines \"i j\"");
  std::vector<std::pair<int, int>> pairs;
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream fields(line);
    long long i = -1, j = -1;
    std::string rest;
    if (!(fields >> i >> j) || (fields >> rest) || i < 0 || j < 0 || i > 1000000000 ||
        j > 1000000000) {
      throw MakeInputError(
          path + " line " + std::to_string(number),
          "'" + detail::ShownText(line) + "'; expected two non-negative integers \"i j\"");
    }
    pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
  }
  return pairs;
}

std::vector<PairTask> FilterPairs(const std::vector<PairTask>& tasks,
                                  const std::vector<std::pair<int, int>>& pairs,
                                  const std::string& where) {
  for (const std::pair<int, int>& pair : pairs) {
    const int i = pair.first, j = pair.second;  // C++17 lambdas cannot capture bindings (clang)
    const bool found = std::any_of(tasks.begin(), tasks.end(), [&](const PairTask& t) {
      return t.target_id == i && t.source_id == j;
    });
    if (!found) {
      throw MakeInputError(where, "pair " + std::to_string(i) + " " + std::to_string(j) +
                                      " is not among the pairs of this protocol and data");
    }
  }
  std::vector<PairTask> kept;
  for (const PairTask& t : tasks) {
    if (std::find(pairs.begin(), pairs.end(), std::make_pair(t.target_id, t.source_id)) !=
        pairs.end()) {
      kept.push_back(t);
    }
  }
  return kept;
}

Shard ParseShard(const std::string& text) {
  const std::string expected = "expected i/N with 0 <= i < N (e.g. 0/4 ... 3/4)";
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw MakeInputError("--shard " + text, expected);
  Shard shard;
  try {
    size_t used_i = 0, used_n = 0;
    shard.index = std::stoi(text.substr(0, slash), &used_i);
    shard.count = std::stoi(text.substr(slash + 1), &used_n);
    if (used_i != slash || used_n != text.size() - slash - 1) throw std::invalid_argument("junk");
  } catch (const std::exception&) {
    throw MakeInputError("--shard " + text, expected);
  }
  if (shard.count < 1 || shard.index < 0 || shard.index >= shard.count) {
    throw MakeInputError("--shard " + text, expected);
  }
  return shard;
}

std::vector<PairTask> ApplyShard(const std::vector<PairTask>& tasks, const Shard& shard) {
  std::vector<PairTask> mine;
  for (size_t k = 0; k < tasks.size(); ++k) {
    if (static_cast<int>(k % shard.count) == shard.index) mine.push_back(tasks[k]);
  }
  return mine;
}

}  // namespace zeroreg
