// Paths the tests use: the repo (from CMake), ../shared beside it, and the CLI binary.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace zeroreg::testing {

inline std::string RepoDir() { return ZEROREG_REPO_DIR; }
inline std::string SharedDir() { return RepoDir() + "/../shared"; }
inline std::string RedkitchenDir() { return SharedDir() + "/data/7scenes-redkitchen"; }
inline std::string CliPath() { return ZEROREG_CLI_PATH; }

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `zeroreg <arguments>` through the shell and captures its output and exit code.
inline CommandResult RunCli(const std::string& arguments) {
  CommandResult result;
  const std::string command = "'" + CliPath() + "' " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace zeroreg::testing
