// The pair-list reader of `eval pairs --list` (src/eval/pair_list.cpp) on a good list and on
// malformed ones: every error names the offending file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "eval/pair_list.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

const char* kMatrix =
    " 1 0 0 0.1\n"
    " 0 1 0 0.2\n"
    " 0 0 1 0.3\n"
    " 0 0 0 1\n";

class EvalPairList : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("zeroreg_pair_list_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name()) /
           "mylist";
    fs::remove_all(dir_.parent_path());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_.parent_path()); }
  void Write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
  }
  // pairs.txt with 0 5, 5 10 and a gt.log holding them in the other order.
  void WriteGood() const {
    Write("pairs.txt", "# kind: frames\n# a comment\n\n0 5\n5 10\n");
    Write("gt.log", std::string("5 10 0\n") + kMatrix + "0 5 0\n" + kMatrix);
  }
  PairList Read(const std::vector<int>& ids = {0, 5, 10}) const {
    return ReadPairList(dir_.string(), ids, "DATA", "scene");
  }
  // Reading throws an InputError whose message names `file` and contains `text`.
  void ExpectError(const std::string& file, const std::string& text,
                   const std::vector<int>& ids = {0, 5, 10}) const {
    try {
      Read(ids);
      ADD_FAILURE() << "no error; expected one naming " << file;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find((dir_ / file).string()), std::string::npos) << what;
      EXPECT_NE(what.find(text), std::string::npos) << what;
    }
  }
  fs::path dir_;
};

TEST_F(EvalPairList, GoodListGivesTasksInPairsTxtOrderWithGtLogTruth) {
  WriteGood();
  const PairList list = Read();
  EXPECT_EQ(list.name, "mylist");
  ASSERT_EQ(list.tasks.size(), 2u);
  EXPECT_EQ(list.tasks[0].target_id, 0);
  EXPECT_EQ(list.tasks[0].source_id, 5);
  EXPECT_EQ(list.tasks[1].target_id, 5);
  EXPECT_EQ(list.tasks[1].source_id, 10);
  EXPECT_EQ(list.tasks[0].benchmark, "mylist");
  EXPECT_EQ(list.tasks[0].target_ref, "DATA@0");
  EXPECT_EQ(list.tasks[0].source_ref, "DATA@5");
  ASSERT_TRUE(list.tasks[0].T_target_source_gt.has_value());
  EXPECT_DOUBLE_EQ((*list.tasks[0].T_target_source_gt)(1, 3), 0.2);
  EXPECT_EQ(list.settings["pairs_txt_sha256"].get<std::string>().size(), 64u);
}

TEST_F(EvalPairList, BadLineInPairsTxtNamesFileAndLine) {
  WriteGood();
  Write("pairs.txt", "# kind: frames\n0 5\n5 x\n");
  ExpectError("pairs.txt", "line 3");
}

// A megabyte line (or kind) is echoed cut to a readable length, with its size stated.
TEST_F(EvalPairList, LongBadLinesAreEchoedShort) {
  WriteGood();
  const std::string junk(1 << 20, 'x');
  for (const std::string& text :
       {"# kind: frames\n0 5\n" + junk + "\n", "# kind: " + junk + "\n0 5\n"}) {
    Write("pairs.txt", text);
    try {
      Read();
      ADD_FAILURE() << "no error for a megabyte line";
    } catch (const InputError& e) {
      EXPECT_LT(std::string(e.what()).size(), 600u);
      EXPECT_NE(std::string(e.what()).find("bytes"), std::string::npos) << e.what();
    }
  }
}

TEST_F(EvalPairList, OtherKindIsRefused) {
  WriteGood();
  Write("pairs.txt", "# kind: fragments\n0 5\n5 10\n");
  ExpectError("pairs.txt", "kind: frames");
}

TEST_F(EvalPairList, GtLogEntryMissingNamesPairsTxtLineAndGtLog) {
  WriteGood();
  Write("gt.log", std::string("0 5 0\n") + kMatrix);
  ExpectError("pairs.txt", "pair 5 10 has no ground truth in " + (dir_ / "gt.log").string());
}

TEST_F(EvalPairList, ExtraGtLogEntryIsRefused) {
  WriteGood();
  Write("gt.log", std::string("0 5 0\n") + kMatrix + "5 10 0\n" + kMatrix + "7 8 0\n" + kMatrix);
  ExpectError("gt.log", "pair 7 8 is not in");
}

TEST_F(EvalPairList, NonNumericMatrixNamesGtLogAndLine) {
  WriteGood();
  Write("gt.log", std::string("0 5 0\n") + kMatrix + "5 10 0\n 1 0 0 0\n 0 1 zero 0\n 0 0 1 0\n" +
                      " 0 0 0 1\n");
  ExpectError("gt.log", "line 8");
}

TEST_F(EvalPairList, NonRigidMatrixIsRefused) {
  WriteGood();
  Write("gt.log",
        std::string("0 5 0\n") + kMatrix + "5 10 0\n 2 0 0 0\n 0 1 0 0\n 0 0 1 0\n" + " 0 0 0 1\n");
  ExpectError("gt.log", "not a rigid transform");
}

TEST_F(EvalPairList, IdMissingFromDataNamesPairsTxtAndData) {
  WriteGood();
  ExpectError("pairs.txt", "frame 10 is not in --data DATA", {0, 5});
}

TEST_F(EvalPairList, MissingGtLogIsNamed) {
  WriteGood();
  fs::remove(dir_ / "gt.log");
  ExpectError("gt.log", "not found");
}

TEST(EvalPairListShared, EveryListOfSharedReadsAgainstItsData) {
  const std::string lists = testing::SharedDir() + "/lists";
  const std::string data = testing::SharedDir() + "/data/hololens-office";
  if (!fs::is_directory(lists + "/hololens-gap1")) GTEST_SKIP() << "no ../shared/lists";
  const auto dataset = OpenDataset(data);
  const PairList list =
      ReadPairList(lists + "/hololens-gap1", dataset->FrameIds(), data, "hololens-office");
  EXPECT_EQ(list.tasks.size(), 119u);
  EXPECT_EQ(list.tasks[0].target_id, 3);
  EXPECT_EQ(list.tasks[0].source_id, 4);
}

}  // namespace
}  // namespace zeroreg
