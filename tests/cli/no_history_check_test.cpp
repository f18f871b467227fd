// scripts/check-no-history.sh (ctest NoHistoryInTrackedFiles) on small git repositories: it fails
// on work-log words in a tracked file, passes on CHANGELOG.md, on untracked files and on the
// recordings sense of "session", and skips a folder that is no git checkout.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_paths.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::RunCommand;

// The labels are assembled here so that this file does not match the check itself.
const std::string kS = std::string("ses") + "sion";
const std::string kIssue = std::string("since is") + "sue ";

class NoHistoryCheck : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::FreshTestDir("zeroreg_history_"); }
  void TearDown() override { fs::remove_all(dir_); }

  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text << "\n";
  }
  void InitAndTrack() const {
    const auto r = RunCommand("cd '" + dir_.string() + "' && git init -q . && git add -A");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  testing::CommandResult Check() const {
    return RunCommand("bash '" + testing::RepoDir() + "/scripts/check-no-history.sh' '" +
                      dir_.string() + "'");
  }

  fs::path dir_;
};

TEST_F(NoHistoryCheck, FailsOnAWorkLogLabelAndNamesTheLine) {
  Write("notes.md", "fine line\nMeasured in the twenty-third " + kS + " on every list.");
  InitAndTrack();
  const auto r = Check();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("notes.md:2:"), std::string::npos) << r.output;
}

TEST_F(NoHistoryCheck, FailsOnSinceIssueAndOnNumberedAndRelativeLabels) {
  for (const std::string& text :
       {"On by default " + kIssue + "12.", "the 3rd " + kS + "'s build", "(second " + kS + ")",
        "this " + kS + "'s experiment", "the previous " + kS + " measured it"}) {
    Write("a.cpp", "// " + text);
    InitAndTrack();
    EXPECT_EQ(Check().exit_code, 1) << text;
  }
}

TEST_F(NoHistoryCheck, PassesOnTheChangelogUntrackedFilesAndRecordingSessions) {
  Write("CHANGELOG.md", kIssue + "12, in the twelfth " + kS + ", ...");
  Write("recordings.md", "A second " + kS + " may be darker; merge two " + kS + "s of a room.");
  InitAndTrack();
  Write("untracked.md", "the fourteenth " + kS);
  const auto r = Check();
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(NoHistoryCheck, SkipsAFolderThatIsNoGitCheckout) {
  Write("notes.md", "the twelfth " + kS);
  const auto r = Check();
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace zeroreg
