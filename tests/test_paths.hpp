// Paths the tests use: the repo (from CMake), ../shared beside it, and the CLI binary.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace zeroreg::testing {

inline std::string RepoDir() { return ZEROREG_REPO_DIR; }
inline std::string SharedDir() { return RepoDir() + "/../shared"; }
inline std::string RedkitchenDir() { return SharedDir() + "/data/7scenes-redkitchen"; }
inline std::string CliPath() { return ZEROREG_CLI_PATH; }

// An empty folder of the running test's own: PREFIX, the process id and the test's name under the
// system's temporary folder (so that tests running at once never share one), emptied first.
inline std::filesystem::path FreshTestDir(const std::string& prefix) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      (prefix + std::to_string(::getpid()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `command` through the shell and captures its output (stdout and stderr) and exit code.
inline CommandResult RunCommand(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// Runs `zeroreg <arguments>` through the shell and captures its output and exit code. With
// timeout_seconds > 0 the command is killed after that long (exit code 124), so a test of
// something that used to hang fails instead of hanging.
inline CommandResult RunCli(const std::string& arguments, int timeout_seconds = 0) {
  const std::string limit =
      timeout_seconds > 0 ? "timeout " + std::to_string(timeout_seconds) + " " : "";
  return RunCommand(limit + "'" + CliPath() + "' " + arguments);
}

}  // namespace zeroreg::testing
