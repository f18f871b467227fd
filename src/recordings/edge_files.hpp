// Sharded verification (docs/RECORDINGS.md "Sharded verification"): the candidate pairs of a merge
// or loops run cut into N shards that separate processes or machines verify, each writing its
// verified pairs to an edge file, and the edge files read back by the run that decides and
// optimises. Plain JSON lines; no registration here.
//
// An edge file: the first line a header (format, command, shard I of N, the run's settings, its
// keyframes and every candidate pair), then one line per verified pair of its shard, as
// loops.jsonl's resume records ({"key", "valid", "reason", "path", "inliers", "overlap",
// "T_u_v"}).
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "zeroreg/recordings.hpp"

namespace zeroreg {

// The key of a candidate pair in loops.jsonl and the edge files: both ends' recording and frame.
std::string PairKey(int recording_u, int frame_u, int recording_v, int frame_v);

// "I/N" with 1 <= I <= N. Throws InputError naming `option` and what was expected.
void ParseShardSpec(const std::string& text, const std::string& option, int* index, int* count);

// The candidate indices of shard `index` (1-based) of `count`: the candidates ordered by their
// first keyframe (u), ties in candidate order, cut into `count` contiguous blocks whose sizes
// differ by at most one. Pairs sharing a keyframe mostly land in one shard, so a shard prepares
// fewer keyframes again. Every candidate is in exactly one shard.
std::vector<std::size_t> ShardCandidates(const std::vector<LoopCandidateResult>& candidates,
                                         int index, int count);

// "edges-I-of-N.jsonl".
std::string EdgeFileName(int index, int count);

// The header line of shard `index` of `count`. `keyframes`: (recording, frame) per keyframe.
nlohmann::json EdgeFileHeader(const std::string& command, const nlohmann::json& settings,
                              const std::vector<std::pair<int, int>>& keyframes,
                              const std::vector<LoopCandidateResult>& candidates, int index,
                              int count);

// What the edge files of every shard of one run hold together.
struct EdgeFileSet {
  std::vector<std::pair<int, int>> keyframes;  // (recording, frame)
  // Every candidate pair: u, v, place_score and rank (nothing verified in them).
  std::vector<LoopCandidateResult> candidates;
  // Per pair key, its verified record (the resume records of loops.jsonl).
  std::map<std::string, nlohmann::json> records;
};

// Reads the edge files of a run made with `settings` (what settings.json holds) and `command`.
// Throws InputError naming `option` and the file when one cannot be read or is no edge file,
// was made by another command, with other recordings or settings (naming the keys that differ),
// from other keyframes or candidates than the others, or is of another shard count; when a shard
// of 1..N has no file or two; or when a file lacks some of its shard's pairs (a shard cut short).
EdgeFileSet ReadEdgeFiles(const std::vector<std::string>& paths, const std::string& command,
                          const nlohmann::json& settings, const std::string& option);

// One edge file read as it is (the header checked against `expected_header` when the file is to be
// resumed): its records by key. Throws InputError naming the file when its header differs.
std::map<std::string, nlohmann::json> ReadEdgeFileForResume(const std::string& path,
                                                            const nlohmann::json& expected_header);

}  // namespace zeroreg
