// Sub-commands of the `zeroreg` command-line tool. Each Add* registers its options on the parent
// app and returns a runner called when that sub-command was chosen.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace zeroreg::cli {

// Exit codes, documented in the README.
constexpr int kExitOk = 0;
constexpr int kExitRegistrationFailed = 1;  // ran, but the result is not valid (see "reason")
constexpr int kExitBadInput = 2;            // a file or argument cannot be used
constexpr int kExitInternalError = 3;

using Runner = std::function<int()>;
Runner AddRegisterCommand(CLI::App& app);
Runner AddFuseCommand(CLI::App& app);
Runner AddInfoCommand(CLI::App& app);
Runner AddEvalCommand(CLI::App& app);
Runner AddReportCommand(CLI::App& app);
Runner AddBenchModelsCommand(CLI::App& app);
Runner AddMergeCommand(CLI::App& app);  // cmd_merge.cpp
Runner AddLoopsCommand(CLI::App& app);
// `eval sessions` (cmd_eval_sessions.cpp): adds the subcommand to `eval`, sets its runner.
CLI::App* AddEvalSessionsCommand(CLI::App& eval, Runner* run);

}  // namespace zeroreg::cli
