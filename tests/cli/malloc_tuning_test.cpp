// glibc's malloc tunables (apps/tuned_environment.cpp): the environment they are added to, that
// they reach zeroreg-core by every route, and that they change no result.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/cli_fixture.hpp"
#include "test_paths.hpp"
#include "tuned_environment.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing::RedkitchenDir;
using testing::RunCli;

std::vector<std::string> Tuned(std::vector<std::string> env) {
  std::vector<char*> pointers;
  for (std::string& e : env) pointers.push_back(e.data());
  pointers.push_back(nullptr);
  char** out = cli::TunedEnvironment(pointers.data());
  std::vector<std::string> result;
  if (out == nullptr) return result;
  for (char** e = out; *e; ++e) result.emplace_back(*e);
  std::free(out);  // the new GLIBC_TUNABLES string is left: a few bytes, once per test
  return result;
}

TEST(TunedEnvironment, AddsTheTunablesAndTheMarkerAndKeepsEverythingElse) {
  const auto env = Tuned({"HOME=/root", "PATH=/bin"});
  ASSERT_EQ(env.size(), 4u);
  EXPECT_EQ(env[0], "HOME=/root");
  EXPECT_EQ(env[1], "PATH=/bin");
  EXPECT_EQ(env[2],
            "GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:"
            "glibc.malloc.top_pad=67108864:glibc.malloc.arena_max=2");
  EXPECT_EQ(env[3], "ZEROREG_MALLOC_TUNING=applied");
}

TEST(TunedEnvironment, KeepsTheUsersOwnTunables) {
  const auto env = Tuned({"GLIBC_TUNABLES=glibc.malloc.top_pad=0:glibc.cpu.x86_shstk=on", "A=1"});
  ASSERT_EQ(env.size(), 3u);
  EXPECT_EQ(env[0], "A=1");
  EXPECT_EQ(env[1],
            "GLIBC_TUNABLES=glibc.malloc.top_pad=0:glibc.cpu.x86_shstk=on:glibc.malloc.hugetlb=1:"
            "glibc.malloc.mmap_threshold=33554432:glibc.malloc.arena_max=2");
}

TEST(TunedEnvironment, NothingWhenSwitchedOffAppliedOrAllSetByTheUser) {
  EXPECT_TRUE(Tuned({"ZEROREG_MALLOC_TUNING=off"}).empty());
  EXPECT_TRUE(Tuned({"ZEROREG_MALLOC_TUNING=applied"}).empty());
  EXPECT_TRUE(Tuned({"GLIBC_TUNABLES=glibc.malloc.hugetlb=0:glibc.malloc.mmap_threshold=1:"
                     "glibc.malloc.top_pad=0:glibc.malloc.arena_max=8"})
                  .empty());
  // A variable whose name only starts like the switch is not the switch.
  EXPECT_EQ(Tuned({"ZEROREG_MALLOC_TUNING_X=off"}).size(), 3u);
}

std::string InfoLine() {
  const auto r = RunCli("info", 0);
  if (r.exit_code != 0) return "exit " + std::to_string(r.exit_code) + ": " + r.output;
  const std::size_t at = r.output.find("malloc tuning:");
  return at == std::string::npos ? r.output : r.output.substr(at, r.output.find('\n', at) - at);
}

class EnvironmentVariable {
 public:
  // value nullptr: unset while the object lives.
  EnvironmentVariable(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~EnvironmentVariable() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// The user's own environment must not decide what these tests see.
class MallocTuning : public ::testing::Test {
 protected:
  EnvironmentVariable no_switch_{"ZEROREG_MALLOC_TUNING", nullptr};
  EnvironmentVariable no_tunables_{"GLIBC_TUNABLES", nullptr};
};

TEST_F(MallocTuning, ReachesTheCoreThroughTheLauncher) {
  EXPECT_EQ(InfoLine(),
            "malloc tuning: applied (GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.mmap_"
            "threshold=33554432:glibc.malloc.top_pad=67108864:glibc.malloc.arena_max=2)");
}

TEST_F(MallocTuning, SwitchedOffAndUserSettingsKept) {
  {
    EnvironmentVariable off("ZEROREG_MALLOC_TUNING", "off");
    EXPECT_EQ(InfoLine(), "malloc tuning: off (GLIBC_TUNABLES=)");
  }
  EnvironmentVariable user("GLIBC_TUNABLES", "glibc.malloc.top_pad=0");
  EXPECT_EQ(InfoLine(),
            "malloc tuning: applied (GLIBC_TUNABLES=glibc.malloc.top_pad=0:glibc.malloc.hugetlb=1:"
            "glibc.malloc.mmap_threshold=33554432:glibc.malloc.arena_max=2)");
}

TEST_F(MallocTuning, TheCoreRunDirectlyTunesItself) {
  const std::string core = (fs::path(testing::CliPath()).parent_path() / "zeroreg-core").string();
  const auto r = testing::RunCommand("'" + core + "' info");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("malloc tuning: applied (GLIBC_TUNABLES=glibc.malloc.hugetlb=1:"),
            std::string::npos)
      << r.output;
}

TEST_F(MallocTuning, SameRegistrationWithAndWithoutIt) {
  const std::string args = "register --source '" + RedkitchenDir() + "@20' --target '" +
                           RedkitchenDir() + "@0' --with-correspondences --out ";
  const std::string a = (fs::temp_directory_path() / "zeroreg_tuned.json").string();
  const std::string b = (fs::temp_directory_path() / "zeroreg_untuned.json").string();
  const auto ra = RunCli(args + a);
  testing::CommandResult rb;
  {
    EnvironmentVariable off("ZEROREG_MALLOC_TUNING", "off");
    rb = RunCli(args + b);
  }
  ASSERT_EQ(ra.exit_code, 0) << ra.output;
  ASSERT_EQ(rb.exit_code, 0) << rb.output;
  EXPECT_EQ(testing::TakeResultWithoutTimings(a), testing::TakeResultWithoutTimings(b));
}

}  // namespace
}  // namespace zeroreg
