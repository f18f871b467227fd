#include "config_options.hpp"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg::cli {
namespace {

std::string Format(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// A validator that accepts `text` when it is a number (an integer if asked) for which `ok` holds.
CLI::Validator NumberValidator(const std::string& expected, bool integer,
                               const std::function<bool(double)>& ok) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(text.c_str(), &end);
        // strtod reads "inf" and "nan" too; no option here takes either.
        const bool number = !text.empty() && *end == '\0' && errno != ERANGE && std::isfinite(x);
        if (!number || (integer && x != static_cast<double>(static_cast<long long>(x))) || !ok(x)) {
          return "is " + text + "; expected " + expected;
        }
        return "";
      },
      expected);
}

std::uint64_t ParseSeed(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  const bool digits_only =
      !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits_only || *end != '\0' || errno == ERANGE) {
    throw MakeInputError("--seed " + text, "expected an integer in [0, 18446744073709551615]");
  }
  return value;
}

}  // namespace

CLI::Validator AtLeast(double min, bool integer) {
  return NumberValidator((integer ? "an integer >= " : "a number >= ") + Format(min), integer,
                         [min](double x) { return x >= min; });
}

CLI::Validator GreaterThan(double min) {
  return NumberValidator("a number > " + Format(min), false, [min](double x) { return x > min; });
}

CLI::Validator InRange(double min, double max, bool integer) {
  return NumberValidator(std::string(integer ? "an integer" : "a number") + " in [" + Format(min) +
                             ", " + Format(max) + "]",
                         integer, [min, max](double x) { return x >= min && x <= max; });
}

std::string PositiveNumber(const std::string& text) {
  double v = 0;
  try {
    v = std::stod(text);
  } catch (const std::exception&) {
    return "'" + text + "' is not a number; expected a positive number";
  }
  return std::isfinite(v) && v > 0 ? "" : "'" + text + "': expected a positive number";
}

void CheckOutputFile(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (fs::is_directory(p, ec)) {
    throw MakeInputError(option + " " + path, "is a folder; expected a file name");
  }
  if (!fs::is_directory(parent, ec)) {
    throw MakeInputError(option + " " + path,
                         "folder " + parent.string() + " does not exist; create it first");
  }
  if (::access(parent.c_str(), W_OK) != 0) {
    throw MakeInputError(option + " " + path, "folder " + parent.string() + " is not writable");
  }
}

void AddConfigOptions(CLI::App& app, ConfigOptions* o) {
  app.add_option("--config,-c", o->config_file, "pipeline config JSON (docs/CONFIG.md)");
  app.add_option("--set", o->overrides, "override one config key: section.key=value (repeatable)");
  app.add_option("--seed", o->seed, "random seed, an integer >= 0 (default 0)");
  app.add_option("--features", o->features, "feature backend: xfeat (default) or sift");
  app.add_option("--assets", o->assets,
                 "model folder, must exist (default: $ZEROREG_ASSETS, then <repo>/assets, then "
                 "the installed share/zeroreg/assets; docs/INSTALL.md)");
}

PipelineConfig BuildConfig(const ConfigOptions& o) {
  PipelineConfig config = o.config_file.empty() ? PipelineConfig() : ReadConfigFile(o.config_file);
  if (!o.seed.empty()) config.seed = ParseSeed(o.seed);
  if (!o.features.empty()) config.features.backend = o.features;
  if (!o.assets.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_directory(o.assets, ec)) {
      throw MakeInputError("--assets " + o.assets, "folder does not exist");
    }
    config.assets_dir = o.assets;
  }
  for (const std::string& assignment : o.overrides) ApplyConfigOverride(assignment, &config);
  return config;
}

bool GivesTopLevelKey(const ConfigOptions& o, const std::string& key) {
  for (const std::string& assignment : o.overrides) {
    if (assignment.compare(0, key.size() + 1, key + "=") == 0) return true;
  }
  if (o.config_file.empty()) return false;
  const nlohmann::json file = detail::ReadJsonFile(o.config_file, "config file");
  return file.is_object() && file.contains(key);
}

}  // namespace zeroreg::cli
