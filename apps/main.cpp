// zeroreg: zero-shot registration of RGB-D scans (ZeroReg, CVPR 2025).
#include <algorithm>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "commands.hpp"
#include "io/shown.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/version.hpp"

namespace {

// Levenshtein distance (insertions, deletions, substitutions), for "did you mean".
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// When a command level needs a subcommand and none was recognised, CLI11 only says "A subcommand
// is required". This names the word that was given (the first argument after the last recognised
// command that is not an option), the nearest command when it is a likely misspelling, and the
// list of commands. Returns false when no command level is missing one.
bool ExplainMissingSubcommand(CLI::App& app, int argc, char** argv) {
  CLI::App* level = &app;
  int position = 1;  // argv index after the last recognised command name
  for (;;) {
    const std::vector<CLI::App*> parsed = level->get_subcommands();
    if (parsed.empty()) break;
    level = parsed.front();
    for (int i = position; i < argc; ++i) {
      if (level->check_name(argv[i])) {
        position = i + 1;
        break;
      }
    }
  }
  const std::vector<CLI::App*> choices = level->get_subcommands({});
  if (choices.empty()) return false;
  std::string names;
  for (const CLI::App* sub : choices) names += (names.empty() ? "" : ", ") + sub->get_name();
  const std::string command = level == &app ? "zeroreg" : "zeroreg " + level->get_name();
  std::string word;
  for (int i = position; i < argc && word.empty(); ++i) {
    if (argv[i][0] != '-') word = argv[i];
  }
  if (word.empty()) {
    std::cerr << "error: " << command << " needs a command; expected one of: " << names << "\n";
    return true;
  }
  std::string nearest;
  size_t best = std::string::npos;
  for (const CLI::App* sub : choices) {
    const size_t d = EditDistance(word, sub->get_name());
    if (d < best) {
      best = d;
      nearest = sub->get_name();
    }
  }
  std::cerr << "error: " << command << ": unknown command '" << zeroreg::detail::ShownText(word)
            << "'";
  // A misspelling: at most a third of the letters wrong (at least 1, so "evl" finds "eval").
  if (best <= std::max<size_t>(1, nearest.size() / 3)) {
    std::cerr << " (did you mean '" << nearest << "'?)";
  }
  std::cerr << "; expected one of: " << names << "\n";
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace zeroreg::cli;
  CLI::App app{"zeroreg: register two RGB-D scans with 2D foundation models, no 3D training"};
  app.set_version_flag("--version", "zeroreg " ZEROREG_VERSION);
  app.require_subcommand(1);
  std::map<CLI::App*, Runner> runners;
  auto add = [&](const char* name, Runner (*adder)(CLI::App&), const char* help) {
    CLI::App* sub = app.add_subcommand(name, help);
    runners[sub] = adder(*sub);
  };
  add("register", AddRegisterCommand, "estimate T_target_source between two scans");
  add("fuse", AddFuseCommand, "TSDF-fuse frames into a 3DMatch-style fragment (cached)");
  add("info", AddInfoCommand, "show the effective config, assets and a scan's contents");
  add("eval", AddEvalCommand, "evaluate on 3DMatch/3DLoMatch or frame pairs, with baselines");
  add("report", AddReportCommand, "make a self-contained HTML page of a register or eval folder");
  add("merge", AddMergeCommand, "place recording B in recording A's frame (T_A_B, one map)");
  add("loops", AddLoopsCommand, "loop closures of one sequence, then its optimised trajectory");
  add("bench-models", AddBenchModelsCommand,
      "time every ONNX model per image on each inference engine");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_name() == "RequiredError" && ExplainMissingSubcommand(app, argc, argv)) {
      std::cerr << "Run with --help for more information.\n";
      return kExitBadInput;
    }
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    for (const auto& [sub, run] : runners) {
      if (sub->parsed()) return run();
    }
  } catch (const zeroreg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return kExitInternalError;
  }
  return kExitInternalError;
}
