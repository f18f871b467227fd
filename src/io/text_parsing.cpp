#include "io/text_parsing.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/shown.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg::detail {

namespace fs = std::filesystem;

void RequireFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw MakeInputError(path, what + " not found (no such file)");
  }
  if (!fs::is_regular_file(path, ec)) {
    throw MakeInputError(path, what + " is not a regular file");
  }
}

nlohmann::json ReadJsonFile(const std::string& path, const std::string& what) {
  RequireFile(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MakeInputError(path, what + " cannot be opened for reading");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw MakeInputError(path, what + " is not valid JSON (" + e.what() + ")");
  }
}

std::string DumpJson(const nlohmann::json& json, int indent) {
  return json.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

// Writes all of `text` to `fd`, retrying interrupted and partial writes; 0, or the errno of the
// failure (EIO for a write that made no progress).
int WriteAll(int fd, const std::string& text) {
  size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    written += static_cast<size_t>(n);
  }
  return 0;
}

// Writes `text` into the existing non-regular file `path` (a device, a FIFO, a terminal) as a
// shell's `>` would: such a file is an endpoint, not a document to replace.
void WriteThrough(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
  if (fd < 0)
    throw MakeInputError(path, std::string("cannot be written (") + std::strerror(errno) + ")");
  if (const int error = WriteAll(fd, text)) {
    ::close(fd);
    throw MakeInputError(path, std::string("cannot be written (") + std::strerror(error) + ")");
  }
  if (::close(fd) != 0 && errno != EINTR) {
    throw MakeInputError(path, std::string("cannot be written (") + std::strerror(errno) + ")");
  }
}

// The file a chain of symbolic links ends at (the path itself when it is not a link), so that
// replacing it keeps the links. Throws InputError naming `path` for a loop.
fs::path FollowLinks(const fs::path& path) {
  fs::path current = path;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(current, ec))) return current;
    const fs::path next = fs::read_symlink(current, ec);
    if (ec) throw MakeInputError(path.string(), "cannot read the link (" + ec.message() + ")");
    current = next.is_absolute() ? next : (current.parent_path() / next).lexically_normal();
  }
  throw MakeInputError(path.string(), "is a loop of symbolic links; expected a file name");
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::string& text) {
  fs::path target(path);
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0) {
    if (S_ISDIR(info.st_mode)) throw MakeInputError(path, "is a folder; expected a file name");
    // A device, FIFO or socket (also through a link: /dev/stdout): renaming a file over it would
    // replace the device node or the link, so the text is written into it instead.
    if (!S_ISREG(info.st_mode)) return WriteThrough(path, text);
  }
  // A link (to a regular file, or dangling): the file it names is replaced and the link kept.
  target = FollowLinks(target);
  // Same folder, so the rename stays on one file system; the pid keeps two writers apart.
  const fs::path temporary =
      target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(getpid()));
  const auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(temporary, ec);
    return MakeInputError(path, "cannot be written (" + why + ")");
  };
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw fail("cannot create " + temporary.string() + ": " + std::strerror(errno));
  if (const int error = WriteAll(fd, text)) {
    ::close(fd);
    throw fail(std::strerror(error));
  }
  // The data reaches the disk before the rename makes it the file: after a crash or power loss
  // the file is the old one or the new one, never an empty one (ext4 and XFS may otherwise commit
  // the rename first).
  const bool synced = ::fsync(fd) == 0;
  const int sync_error = errno;
  if (::close(fd) != 0) throw fail(std::strerror(errno));
  if (!synced) throw fail(std::strerror(sync_error));
  std::error_code ec;
  fs::rename(temporary, target, ec);
  if (ec) throw fail(ec.message());
  // And the rename itself (the folder's entry) is on the disk when this returns.
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const int folder_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder_fd >= 0) {
    ::fsync(folder_fd);  // best effort: some file systems refuse fsync on a folder
    ::close(folder_fd);
  }
}

double LimitFromEnvironment(const char* name, double default_value) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return default_value;
  double value = 0.0;
  if (!ParseDouble(text, &value) || !std::isfinite(value) || value <= 0.0) {
    throw MakeInputError(
        name, std::string("environment variable is '") + text + "'; expected a number > 0");
  }
  return value;
}

bool ParseDouble(const std::string& token, double* value) {
  if (token.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size()) return false;
  // ERANGE on underflow (denormals, e.g. 1e-320) is harmless; on overflow strtod gives +-HUGE_VAL,
  // which the callers reject as non-finite.
  *value = v;
  return true;
}

std::string WithoutByteOrderMark(const std::string& line) {
  // Windows editors (Notepad) start UTF-8 text with EF BB BF; it is not part of the first value.
  return line.rfind("\xEF\xBB\xBF", 0) == 0 ? line.substr(3) : line;
}

std::vector<double> ReadNumbers(const std::string& path, const std::string& what) {
  RequireFile(path, what);
  std::ifstream in(path);
  if (!in) throw MakeInputError(path, what + " cannot be opened for reading");
  std::vector<double> numbers;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1) line = WithoutByteOrderMark(line);
    std::istringstream tokens(line);
    std::string token;
    while (tokens >> token) {
      double v = 0.0;
      if (!ParseDouble(token, &v)) {
        const std::string invisible = InvisibleCharacters(token);
        throw MakeInputError(path, "line " + std::to_string(line_number) + ": '" +
                                       ShownText(token) + "' is not a number (" +
                                       (invisible.empty() ? ""
                                                          : "it holds the invisible character(s) " +
                                                                invisible + "; ") +
                                       what + " must hold only numbers)");
      }
      numbers.push_back(v);
    }
  }
  return numbers;
}

void CheckRigid(const Transform& T, const std::string& where) {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(T(r, c))) {
        throw MakeInputError(where, "non-finite value at row " + std::to_string(r + 1) +
                                        ", column " + std::to_string(c + 1) +
                                        "; expected a finite rigid 4x4 transform");
      }
    }
  }
  const Eigen::RowVector4d expected_last(0, 0, 0, 1);
  if ((T.row(3) - expected_last).cwiseAbs().maxCoeff() > 1e-6) {
    std::ostringstream row;
    row << T.row(3);
    throw MakeInputError(where, "bad last row (" + row.str() + "); expected 0 0 0 1");
  }
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double orthonormality_error =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality_error > 1e-2 || R.determinant() <= 0.0) {
    std::ostringstream msg;
    msg << "rotation is not rigid (max |R^T R - I| = " << orthonormality_error
        << ", det R = " << R.determinant()
        << "); expected an orthonormal rotation with det +1 (tolerance 1e-2)";
    throw MakeInputError(where, msg.str());
  }
}

Transform RigidFromNumbers(const std::vector<double>& numbers, const std::string& where) {
  if (numbers.size() != 16) {
    throw MakeInputError(where, "holds " + std::to_string(numbers.size()) +
                                    " numbers; expected 16 numbers (a 4x4 row-major transform)");
  }
  Transform T;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) T(r, c) = numbers[static_cast<size_t>(4 * r + c)];
  }
  CheckRigid(T, where);
  return T;
}

void CheckDepthScale(double depth_scale, const std::string& where) {
  if (!std::isfinite(depth_scale) || depth_scale <= 0.0) {
    throw MakeInputError(where, "depth_scale " + ShownNumber(depth_scale) +
                                    " is invalid; expected a finite number > 0 (raw units per "
                                    "metre, e.g. 1000 for millimetres)");
  }
}

std::string ResolvePath(const std::string& base_dir, const std::string& path) {
  const fs::path p(path);
  if (p.is_absolute() || base_dir.empty()) return path;
  return (fs::path(base_dir) / p).lexically_normal().string();
}

}  // namespace zeroreg::detail
