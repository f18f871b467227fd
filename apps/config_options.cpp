#include "config_options.hpp"

#include "zeroreg/json.hpp"

namespace zeroreg::cli {

void AddConfigOptions(CLI::App& app, ConfigOptions* o) {
  app.add_option("--config,-c", o->config_file, "pipeline config JSON (docs/CONFIG.md)");
  app.add_option("--set", o->overrides, "override one config key: section.key=value (repeatable)");
  app.add_option("--seed", o->seed, "random seed (default 0)");
  app.add_option("--features", o->features, "feature backend: xfeat (default) or sift");
  app.add_option("--assets", o->assets,
                 "model folder (default: $ZEROREG_ASSETS, then <repo>/assets, then the "
                 "installed share/zeroreg/assets; docs/INSTALL.md)");
}

PipelineConfig BuildConfig(const ConfigOptions& o) {
  PipelineConfig config = o.config_file.empty() ? PipelineConfig() : ReadConfigFile(o.config_file);
  if (o.seed) config.seed = *o.seed;
  if (!o.features.empty()) config.features.backend = o.features;
  if (!o.assets.empty()) config.assets_dir = o.assets;
  for (const std::string& assignment : o.overrides) ApplyConfigOverride(assignment, &config);
  return config;
}

}  // namespace zeroreg::cli
