// Options of the commands over whole recordings (merge, loops, eval sessions).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "config_options.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg::cli {

struct RecordingsOptions {
  std::string out;
  RecordingsConfig config;
  int cache_mib = 384;
  bool no_cloud = false, quiet = false;
  ConfigOptions pipeline;
  std::string shard;               // --shard I/N
  std::vector<std::string> edges;  // --edges FILE...
};

void AddRecordingsOptions(CLI::App& app, RecordingsOptions* options);
// --shard and --edges (merge and loops).
void AddShardOptions(CLI::App& app, RecordingsOptions* options);
RecordingsConfig ConfigFromOptions(const RecordingsOptions& options);
// A recording from its specification (DIR or DIR@FIRST-LAST) and its poses: "auto", "gt", "none"
// or a TUM trajectory file; `option` names the poses' option in messages.
RecordingInput RecordingFromOptions(const std::string& spec, const std::string& poses,
                                    const std::string& option);

}  // namespace zeroreg::cli
