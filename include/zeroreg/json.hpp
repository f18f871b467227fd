// JSON forms of the config and the result (docs/CONFIG.md). The config's keys are the struct
// field names, grouped by stage: {"features": {"backend": "sift"}, "ransac": {...}, "seed": 0}.
// Keys not given keep their defaults; unknown keys are an error (they are usually typos).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

nlohmann::json ConfigToJson(const PipelineConfig& config);
// Applies the keys of `json` on top of `config`. `where` names the source (a file or "--set") in
// error messages. Throws InputError on unknown keys, wrong value types or values out of range
// (docs/CONFIG.md, "Accepted values"); the message names `where` and the key path.
void ApplyConfigJson(const nlohmann::json& json, const std::string& where, PipelineConfig* config);
// Checks every value of `config` (types, ranges, finiteness, min < max pairs) as if it had been
// read from JSON: the Pipeline calls it, so configs built in code are checked too. `where` starts
// the message.
void ValidateConfig(const PipelineConfig& config, const std::string& where);
// Throws InputError naming the file if it is not a regular file, not JSON or not a valid config.
PipelineConfig ReadConfigFile(const std::string& path);
// Applies one "section.key=value" override (value parsed as JSON, else as a string).
void ApplyConfigOverride(const std::string& assignment, PipelineConfig* config);

nlohmann::json TransformToJson(const Transform& T);  // 4 rows of 4 numbers
nlohmann::json ResultToJson(const RegistrationResult& result, bool include_correspondences);

}  // namespace zeroreg
