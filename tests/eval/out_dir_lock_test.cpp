// A results folder is written by one `zeroreg eval` at a time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "eval/session.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

TEST(OutDirLock, SecondWriterIsRefusedUntilTheFirstIsDone) {
  const fs::path dir = fs::temp_directory_path() / ("zeroreg_lock_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  {
    const OutDirLock first(dir.string());
    try {
      const OutDirLock second(dir.string());
      ADD_FAILURE() << "a second lock was granted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(dir.string() + ": another `zeroreg eval`"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW(OutDirLock again(dir.string()));  // released with the first
  fs::remove_all(dir);
}

}  // namespace
}  // namespace zeroreg
