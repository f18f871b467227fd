#include "recordings/edge_files.hpp"

#include <algorithm>
#include <exception>
#include <fstream>
#include <numeric>
#include <sstream>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "zeroreg-edges-1";

std::string ShardName(int index, int count) {
  return std::to_string(index) + "/" + std::to_string(count);
}

// The header line, parsed; throws when the file is no edge file.
json ReadHeader(std::ifstream& in, const std::string& where) {
  std::string line;
  json header;
  if (std::getline(in, line)) {
    try {
      header = json::parse(line);
    } catch (const std::exception&) {
      header = json();
    }
  }
  if (!header.is_object() || header.value("format", std::string()) != kFormat ||
      !header.contains("shard") || !header.contains("shards") || !header.contains("settings") ||
      !header.contains("keyframes") || !header.contains("candidates")) {
    throw InputError(where + ": not an edge file (expected the first line written by " +
                     "`zeroreg merge` or `zeroreg loops` with --shard I/N)");
  }
  return header;
}

// The records after the header, by key. A line cut short (a killed shard) is left out: its pair
// counts as not verified.
std::map<std::string, json> ReadRecords(std::ifstream& in) {
  std::map<std::string, json> records;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    try {
      const json record = json::parse(line);
      records[record.at("key").get<std::string>()] = record;
    } catch (const std::exception&) {
    }
  }
  return records;
}

std::vector<LoopCandidateResult> CandidatesFromJson(const json& list) {
  std::vector<LoopCandidateResult> candidates;
  for (const json& c : list) {
    LoopCandidateResult r;
    r.u = c.at(0).get<int>();
    r.v = c.at(1).get<int>();
    r.place_score = c.at(2).get<double>();
    r.rank = c.at(3).get<int>();
    candidates.push_back(r);
  }
  return candidates;
}

}  // namespace

std::string PairKey(int recording_u, int frame_u, int recording_v, int frame_v) {
  return std::to_string(recording_u) + ":" + std::to_string(frame_u) + "-" +
         std::to_string(recording_v) + ":" + std::to_string(frame_v);
}

void ParseShardSpec(const std::string& text, const std::string& option, int* index, int* count) {
  int i = 0, n = 0;
  char slash = 0;
  std::string rest;
  std::istringstream in(text);
  if (!(in >> i >> slash >> n) || slash != '/' || (in >> rest) || n < 1 || i < 1 || i > n) {
    throw InputError(option + " " + text +
                     ": expected I/N, shard I of N with 1 <= I <= N (e.g. 1/2 and 2/2)");
  }
  *index = i;
  *count = n;
}

std::vector<std::size_t> ShardCandidates(const std::vector<LoopCandidateResult>& candidates,
                                         int index, int count) {
  std::vector<std::size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return candidates[a].u < candidates[b].u; });
  const std::size_t n = order.size(), k = static_cast<std::size_t>(count);
  const std::size_t begin = n * static_cast<std::size_t>(index - 1) / k;
  const std::size_t end = n * static_cast<std::size_t>(index) / k;
  std::vector<std::size_t> shard(order.begin() + static_cast<std::ptrdiff_t>(begin),
                                 order.begin() + static_cast<std::ptrdiff_t>(end));
  std::sort(shard.begin(), shard.end());
  return shard;
}

std::string EdgeFileName(int index, int count) {
  return "edges-" + std::to_string(index) + "-of-" + std::to_string(count) + ".jsonl";
}

json EdgeFileHeader(const std::string& command, const json& settings,
                    const std::vector<std::pair<int, int>>& keyframes,
                    const std::vector<LoopCandidateResult>& candidates, int index, int count) {
  json k = json::array(), c = json::array();
  for (const auto& [recording, frame] : keyframes) k.push_back({recording, frame});
  for (const LoopCandidateResult& r : candidates) c.push_back({r.u, r.v, r.place_score, r.rank});
  return {{"format", kFormat},    {"command", command}, {"shard", index}, {"shards", count},
          {"settings", settings}, {"keyframes", k},     {"candidates", c}};
}

EdgeFileSet ReadEdgeFiles(const std::vector<std::string>& paths, const std::string& command,
                          const json& settings, const std::string& option) {
  if (paths.empty()) throw InputError(option + ": no edge file given");
  EdgeFileSet set;
  int count = 0;
  std::string first_path;
  json first_header;
  std::map<int, std::string> file_of_shard;
  std::map<int, std::map<std::string, json>> records_of_shard;
  for (const std::string& path : paths) {
    const std::string where = option + " " + path;
    std::ifstream in(path);
    if (!in) throw InputError(where + ": cannot read the edge file");
    const json header = ReadHeader(in, where);
    if (header.value("command", std::string()) != command) {
      throw InputError(where + ": written by `zeroreg " + header.value("command", std::string()) +
                       " --shard`, not by `zeroreg " + command + "`");
    }
    if (header.at("settings") != settings) {
      std::string keys;
      for (const auto& [key, value] : settings.items()) {
        if (!header.at("settings").contains(key) || header.at("settings").at(key) != value) {
          keys += (keys.empty() ? "" : ", ") + key;
        }
      }
      throw InputError(where + ": made with other recordings or settings than this run (" +
                       (keys.empty() ? std::string("settings") : keys) +
                       " differ); give this step the recordings and options the shards ran with");
    }
    const int index = header.at("shard").get<int>(), n = header.at("shards").get<int>();
    if (count == 0) {
      count = n;
      first_path = path;
      first_header = header;
    } else if (n != count) {
      throw InputError(where + ": shard " + ShardName(index, n) + ", but " + first_path +
                       " is of " + std::to_string(count) + " shards");
    } else if (header.at("keyframes") != first_header.at("keyframes") ||
               header.at("candidates") != first_header.at("candidates")) {
      throw InputError(where + ": made from other keyframes or candidate pairs than " + first_path +
                       " (other poses, data or program?)");
    }
    if (file_of_shard.count(index) != 0) {
      throw InputError(where + ": shard " + ShardName(index, n) + " again (also " +
                       file_of_shard[index] + ")");
    }
    file_of_shard[index] = path;
    records_of_shard[index] = ReadRecords(in);
  }
  for (int i = 1; i <= count; ++i) {
    if (file_of_shard.count(i) == 0) {
      throw InputError(option + ": no edge file of shard " + ShardName(i, count) +
                       " among the files given (run it with --shard " + ShardName(i, count) +
                       ", or give its file)");
    }
  }
  for (const json& k : first_header.at("keyframes")) {
    set.keyframes.emplace_back(k.at(0).get<int>(), k.at(1).get<int>());
  }
  set.candidates = CandidatesFromJson(first_header.at("candidates"));
  for (const LoopCandidateResult& c : set.candidates) {
    if (c.u < 0 || c.v < 0 || c.u >= static_cast<int>(set.keyframes.size()) ||
        c.v >= static_cast<int>(set.keyframes.size())) {
      throw InputError(option + " " + first_path + ": a candidate pair names no keyframe");
    }
  }
  for (int i = 1; i <= count; ++i) {
    const std::map<std::string, json>& records = records_of_shard[i];
    const std::vector<std::size_t> shard = ShardCandidates(set.candidates, i, count);
    std::size_t missing = 0;
    for (std::size_t c : shard) {
      const auto& u = set.keyframes[static_cast<std::size_t>(set.candidates[c].u)];
      const auto& v = set.keyframes[static_cast<std::size_t>(set.candidates[c].v)];
      const std::string key = PairKey(u.first, u.second, v.first, v.second);
      const auto it = records.find(key);
      if (it == records.end()) {
        ++missing;
      } else {
        set.records[key] = it->second;
      }
    }
    if (missing > 0) {
      throw InputError(option + " " + file_of_shard[i] + ": " + std::to_string(missing) +
                       " of the " + std::to_string(shard.size()) + " pairs of shard " +
                       ShardName(i, count) +
                       " are not verified (the shard was cut short?); run it again with --shard " +
                       ShardName(i, count) + " to finish them");
    }
  }
  return set;
}

std::map<std::string, json> ReadEdgeFileForResume(const std::string& path,
                                                  const json& expected_header) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the edge file to resume it");
  const json header = ReadHeader(in, path);
  if (header != expected_header) {
    throw InputError(path +
                     ": an edge file of another run (other recordings, settings, keyframes or "
                     "candidates); remove it or choose another --out");
  }
  return ReadRecords(in);
}

}  // namespace zeroreg
