// Options shared by the commands that run the pipeline: --config, --set, --seed, --features,
// --assets. Order of precedence: defaults < --config file < the explicit options < --set.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg::cli {

struct ConfigOptions {
  std::string config_file;
  std::vector<std::string> overrides;
  std::optional<std::uint64_t> seed;
  std::string features;
  std::string assets;
};

void AddConfigOptions(CLI::App& app, ConfigOptions* options);
PipelineConfig BuildConfig(const ConfigOptions& options);

}  // namespace zeroreg::cli
