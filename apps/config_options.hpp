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
  std::string seed;  // text: parsed by BuildConfig so that -3 or 2^64 are refused, not wrapped
  std::string features;
  std::string assets;
};

void AddConfigOptions(CLI::App& app, ConfigOptions* options);
// Throws InputError naming the option (--config file, --seed, --assets, --set) that is wrong.
PipelineConfig BuildConfig(const ConfigOptions& options);
// Whether the --config file or a --set gives the top-level config key `key` (e.g. "threads").
// Call it on options BuildConfig accepted: it reads the file again and does not check it.
bool GivesTopLevelKey(const ConfigOptions& options, const std::string& key);

// Validators with messages in the option's own terms ("--gap: is 0; expected an integer >= 1"),
// instead of CLI11's "Value 0 not in range 0.000000 to 1797...".
CLI::Validator AtLeast(double min, bool integer);
CLI::Validator GreaterThan(double min);
CLI::Validator InRange(double min, double max, bool integer);
// CLI11 check of a tolerance (the motion prior's, in register and eval): a positive, finite number
// (CLI11's own PositiveNumber prints DBL_MAX).
std::string PositiveNumber(const std::string& text);

// Refuses an output file whose folder does not exist or is a file, before any work is done.
void CheckOutputFile(const std::string& path, const std::string& option);

}  // namespace zeroreg::cli
