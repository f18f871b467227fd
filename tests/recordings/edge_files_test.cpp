// Sharded verification's pieces without registration: the shard argument, the cut of the
// candidates into shards, and the edge files read back with every way they can be unfit.
#include "recordings/edge_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "test_paths.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string ShardError(const std::string& text) {
  int i = 0, n = 0;
  try {
    ParseShardSpec(text, "--shard", &i, &n);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ShardSpecTest, ReadsIOfNAndRefusesEverythingElseNamingTheOption) {
  int i = 0, n = 0;
  ParseShardSpec("2/3", "--shard", &i, &n);
  EXPECT_EQ(i, 2);
  EXPECT_EQ(n, 3);
  ParseShardSpec("1/1", "--shard", &i, &n);
  EXPECT_EQ(i, 1);
  EXPECT_EQ(n, 1);
  for (const std::string bad : {"0/2", "3/2", "2", "1/0", "-1/2", "1/2x", "a/b", "1-2", ""}) {
    const std::string error = ShardError(bad);
    EXPECT_NE(error.find("--shard " + bad + ": expected I/N"), std::string::npos)
        << bad << ": " << error;
  }
}

std::vector<LoopCandidateResult> Candidates(const std::vector<int>& us) {
  std::vector<LoopCandidateResult> candidates;
  for (std::size_t i = 0; i < us.size(); ++i) {
    LoopCandidateResult c;
    c.u = us[i];
    c.v = 10 + static_cast<int>(i);
    c.place_score = 0.1 * static_cast<double>(i) + 1.0 / 3.0;
    c.rank = static_cast<int>(i % 3);
    candidates.push_back(c);
  }
  return candidates;
}

TEST(ShardCandidatesTest, EveryCandidateInExactlyOneShardOfNearlyEqualSize) {
  const std::vector<LoopCandidateResult> candidates = Candidates({3, 1, 2, 1, 3, 0, 2, 2, 1, 0, 3});
  for (int count = 1; count <= 13; ++count) {
    std::multiset<std::size_t> seen;
    std::size_t smallest = candidates.size(), largest = 0;
    for (int index = 1; index <= count; ++index) {
      const std::vector<std::size_t> shard = ShardCandidates(candidates, index, count);
      EXPECT_TRUE(std::is_sorted(shard.begin(), shard.end()));
      seen.insert(shard.begin(), shard.end());
      smallest = std::min(smallest, shard.size());
      largest = std::max(largest, shard.size());
    }
    EXPECT_EQ(seen.size(), candidates.size()) << count;
    for (std::size_t c = 0; c < candidates.size(); ++c) EXPECT_EQ(seen.count(c), 1u) << count;
    EXPECT_LE(largest - smallest, 1u) << count;
  }
  // Two shards: the pairs of keyframes 0 and 1 in the first, those of 3 in the second.
  for (std::size_t c : ShardCandidates(candidates, 1, 2)) EXPECT_LE(candidates[c].u, 2);
  for (std::size_t c : ShardCandidates(candidates, 2, 2)) EXPECT_GE(candidates[c].u, 2);
}

class EdgeFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshTestDir("zeroreg_edge_files_");
    settings_ = {
        {"command", "merge"}, {"candidates_per_keyframe", 5}, {"keyframe_covisibility", 0.7}};
    keyframes_ = {{0, 460}, {0, 470}, {0, 480}, {0, 490}, {1, 600}, {1, 610}, {1, 620}};
    candidates_ = Candidates({0, 1, 2, 3, 0, 1});
    for (LoopCandidateResult& c : candidates_) c.v = 4 + c.rank;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Shard `index` of `count` written with every pair of it verified, but `leave_out` of them.
  std::string WriteShard(int index, int count, std::size_t leave_out = 0,
                         const json& settings = json()) {
    const std::string path = (dir_ / EdgeFileName(index, count)).string();
    std::ofstream out(path);
    out << EdgeFileHeader("merge", settings.is_null() ? settings_ : settings, keyframes_,
                          candidates_, index, count)
               .dump()
        << "\n";
    const std::vector<std::size_t> shard = ShardCandidates(candidates_, index, count);
    for (std::size_t n = leave_out; n < shard.size(); ++n) {
      const LoopCandidateResult& c = candidates_[shard[n]];
      const auto& u = keyframes_[static_cast<std::size_t>(c.u)];
      const auto& v = keyframes_[static_cast<std::size_t>(c.v)];
      out << json{{"key", PairKey(u.first, u.second, v.first, v.second)},
                  {"valid", true},
                  {"reason", "test"},
                  {"path", "object"},
                  {"inliers", 10 + static_cast<int>(shard[n])},
                  {"overlap", 0.5},
                  {"T_u_v", json::array()}}
                 .dump()
          << "\n";
    }
    return path;
  }

  std::string Error(const std::vector<std::string>& paths) {
    try {
      ReadEdgeFiles(paths, "merge", settings_, "--edges");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
  json settings_;
  std::vector<std::pair<int, int>> keyframes_;
  std::vector<LoopCandidateResult> candidates_;
};

TEST_F(EdgeFilesTest, TwoShardsGiveBackEveryCandidateAndEveryRecordExactly) {
  const EdgeFileSet set =
      ReadEdgeFiles({WriteShard(2, 2), WriteShard(1, 2)}, "merge", settings_, "--edges");
  EXPECT_EQ(set.keyframes, keyframes_);
  ASSERT_EQ(set.candidates.size(), candidates_.size());
  for (std::size_t c = 0; c < candidates_.size(); ++c) {
    EXPECT_EQ(set.candidates[c].u, candidates_[c].u);
    EXPECT_EQ(set.candidates[c].v, candidates_[c].v);
    EXPECT_EQ(set.candidates[c].place_score, candidates_[c].place_score);  // bit for bit
    EXPECT_EQ(set.candidates[c].rank, candidates_[c].rank);
  }
  EXPECT_EQ(set.records.size(), candidates_.size());
}

TEST_F(EdgeFilesTest, UnfitFilesAreRefusedNamingTheOptionAndTheFile) {
  const std::string one = WriteShard(1, 2);
  // A shard missing.
  EXPECT_NE(Error({one}).find("--edges: no edge file of shard 2/2"), std::string::npos)
      << Error({one});
  // A file that is not there, and one that is no edge file.
  const std::string missing = (dir_ / "edges-2-of-2.jsonl").string();
  EXPECT_NE(Error({one, missing}).find("--edges " + missing + ": cannot read"), std::string::npos);
  const std::string other = (dir_ / "loops.jsonl").string();
  std::ofstream(other) << "{\"key\": \"0:1-1:2\"}\n";
  EXPECT_NE(Error({one, other}).find("--edges " + other + ": not an edge file"), std::string::npos);
  // A shard cut short.
  const std::string cut = WriteShard(2, 2, /*leave_out=*/2);
  EXPECT_NE(Error({one, cut})
                .find("--edges " + cut +
                      ": 2 of the 3 pairs of shard 2/2 are not "
                      "verified"),
            std::string::npos)
      << Error({one, cut});
  const std::string two = WriteShard(2, 2);
  EXPECT_EQ(Error({one, two}), "");
  // The same shard twice; shards of another count.
  EXPECT_NE(Error({one, two, one}).find("shard 1/2 again"), std::string::npos);
  const std::string of_three = WriteShard(3, 3);
  EXPECT_NE(Error({one, two, of_three})
                .find("--edges " + of_three + ": shard 3/3, but " + one + " is of 2 shards"),
            std::string::npos);
  // Made with other settings: the keys that differ are named.
  json changed = settings_;
  changed["candidates_per_keyframe"] = 3;
  const std::string foreign = WriteShard(2, 2, 0, changed);
  EXPECT_NE(Error({one, foreign})
                .find("--edges " + foreign +
                      ": made with other recordings or settings than this run "
                      "(candidates_per_keyframe differ)"),
            std::string::npos)
      << Error({one, foreign});
  // Written by the other command.
  EXPECT_THROW(ReadEdgeFiles({one, two}, "loops", settings_, "--edges"), InputError);
}

TEST_F(EdgeFilesTest, ResumeReadsItsOwnFileAndRefusesAnotherRuns) {
  const std::string path = WriteShard(1, 2, 1);
  const json header = EdgeFileHeader("merge", settings_, keyframes_, candidates_, 1, 2);
  EXPECT_EQ(ReadEdgeFileForResume(path, header).size(),
            ShardCandidates(candidates_, 1, 2).size() - 1);
  const json other = EdgeFileHeader("merge", settings_, keyframes_, candidates_, 1, 3);
  EXPECT_THROW(ReadEdgeFileForResume(path, other), InputError);
}

}  // namespace
}  // namespace zeroreg
