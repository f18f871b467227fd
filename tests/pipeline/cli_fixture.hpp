// The fixture of the command-line tests on bad input (cli_test.cpp, bad_inputs_cli_test.cpp): a
// copy of two redkitchen frames to damage, and a checker for the exit code and message.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "test_paths.hpp"

namespace zeroreg::testing {

namespace fs = std::filesystem;

// The JSON a `register --out` wrote to `path`, without its timings (the one part that differs
// between runs of the same input), and the file removed.
inline nlohmann::json TakeResultWithoutTimings(const std::string& path) {
  nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
  j["result"].erase("timings_ms");
  fs::remove(path);
  return j;
}

// A copy of redkitchen frames 0 and 20 in the 3DMatch layout, to be damaged one way per test.
class CliBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshTestDir("zeroreg_cli_");
    fs::copy_file(RedkitchenDir() + "/camera-intrinsics.txt", dir_ / "camera-intrinsics.txt");
    for (const char* id : {"000000", "000020"}) {
      for (const char* ext : {".color.jpg", ".depth.png", ".pose.txt"}) {
        const std::string name = std::string("frame-") + id + ext;
        fs::copy_file(RedkitchenDir() + "/frames/" + name, dir_ / name);
      }
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name), std::ios::binary) << text;
  }
  // Registers frame 20 onto frame 0 of the damaged copy.
  testing::CommandResult Run(const std::string& extra = "") const {
    return RunCli("register --source '" + dir_.string() + "@20' --target '" + dir_.string() +
                  "@0' " + extra);
  }
  static void ExpectClearError(const testing::CommandResult& r, const std::string& file,
                               const std::string& problem) {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(file), std::string::npos) << "message does not name " << file << ":\n"
                                                      << r.output;
    EXPECT_NE(r.output.find(problem), std::string::npos)
        << "message does not say '" << problem << "':\n"
        << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  }

  fs::path dir_;
};

}  // namespace zeroreg::testing
