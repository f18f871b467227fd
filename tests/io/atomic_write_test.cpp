// detail::WriteFileAtomically, the one writer of every result file (register --out, pairs.jsonl,
// run.json, summaries, report.html, fuse.json): a new or regular file is replaced through a
// temporary file and a rename; an output that exists and is not a regular file (a device, a FIFO,
// a link to one) is written through, never renamed over; a link to a regular file keeps the link.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/io_test_util.hpp"
#include "io/text_parsing.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using testing_io::TempDir;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicWrite, RegularFileIsReplacedAndNoTemporaryIsLeft) {
  TempDir dir;
  const std::string path = dir.File("out.json");
  detail::WriteFileAtomically(path, "one\n");
  detail::WriteFileAtomically(path, "two\n");
  EXPECT_EQ(ReadText(path), "two\n");
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    static_cast<void>(entry);
    ++entries;
  }
  EXPECT_EQ(entries, 1);
}

// A FIFO (or a device) is written through: the FIFO stays a FIFO and its reader gets the text.
TEST(AtomicWrite, FifoIsWrittenThroughNotRenamedOver) {
  TempDir dir;
  const std::string fifo = dir.File("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  // A reader that does not wait for a writer, so that the writer's open does not block.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  detail::WriteFileAtomically(fifo, "through the pipe\n");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo))) << "the FIFO was replaced";
  char buffer[64] = {};
  const ssize_t n = ::read(reader, buffer, sizeof(buffer) - 1);
  ::close(reader);
  EXPECT_EQ(std::string(buffer, n > 0 ? static_cast<size_t>(n) : 0), "through the pipe\n");
}

// `--out /dev/stdout` is a link to a descriptor: the link must stay a link; here a link to
// /dev/null stands for it (renaming over /dev/null itself would break the machine).
TEST(AtomicWrite, LinkToADeviceStaysALink) {
  TempDir dir;
  const std::string link = dir.File("null-link");
  fs::create_symlink("/dev/null", link);
  detail::WriteFileAtomically(link, "discarded\n");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link))) << "the link was replaced by a file";
  EXPECT_TRUE(fs::is_character_file(fs::status("/dev/null")));
}

// A device node itself (a second node of the null device, made in the test's folder): written
// into, still a device afterwards.
TEST(AtomicWrite, DeviceNodeIsWrittenThroughNotRenamedOver) {
  TempDir dir;
  const std::string node = dir.File("null");
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    GTEST_SKIP() << "cannot make a device node here (not root)";
  }
  detail::WriteFileAtomically(node, "discarded\n");
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(node))) << "the device node was replaced";
}

// A link to a regular file keeps being the link; the file it names gets the text (atomically).
TEST(AtomicWrite, LinkToARegularFileWritesTheFileItNames) {
  TempDir dir;
  const std::string target = dir.File("real/result.json");
  const std::string link = dir.File("result.json");
  std::ofstream(target) << "old\n";
  fs::create_symlink(target, link);
  detail::WriteFileAtomically(link, "new\n");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(ReadText(target), "new\n");
}

// Writing through a device reports the system's reason: /dev/full is a disk that is full.
// Through a link, so that a writer that renames over its output replaces the link, not the device.
TEST(AtomicWrite, FullDeviceNamesTheReason) {
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "/dev/full is absent";
  TempDir dir;
  const std::string full = dir.File("full");
  fs::create_symlink("/dev/full", full);
  try {
    detail::WriteFileAtomically(full, std::string(100000, 'x'));
    FAIL() << "no error writing to /dev/full";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(full), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST(AtomicWrite, FolderIsRefusedByName) {
  TempDir dir;
  const std::string folder = dir.File("sub/x");
  fs::create_directories(folder);
  try {
    detail::WriteFileAtomically(folder, "text");
    FAIL() << "no error writing over a folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(folder));
}

}  // namespace
}  // namespace zeroreg
