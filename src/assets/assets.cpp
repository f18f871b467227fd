// Locating and verifying model files (DESIGN §5).
#include "zeroreg/assets.hpp"

#include <dlfcn.h>
#include <link.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <tuple>
#include <vector>

#include "assets/assets_internal.hpp"
#include "assets/sha256.hpp"
#include "zeroreg/error.hpp"

#if !defined(ZEROREG_REPO_DIR) || !defined(ZEROREG_INSTALL_ASSETS_DIR)
#error "ZEROREG_REPO_DIR and ZEROREG_INSTALL_ASSETS_DIR come from the build (CMakeLists.txt)"
#endif

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFetchHint = "run bash scripts/fetch-assets.sh";
constexpr const char* kListName = "assets.sha256";

bool IsDirectory(const std::string& path) {
  std::error_code ec;
  return !path.empty() && fs::is_directory(path, ec);
}

std::string JoinPath(const std::string& dir, const std::string& name) {
  if (dir.empty() || dir.back() == '/') return dir + name;
  return dir + "/" + name;
}

bool IsLowerHex64(const std::string& s) {
  if (s.size() != 64) return false;
  for (char c : s) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

// Parses a `sha256sum` style list: "<64 hex>  <relative path>" per line ("*" binary marker
// allowed); blank lines and lines starting with '#' are ignored.
std::map<std::string, std::string> ReadHashList(const std::string& list_path) {
  std::ifstream in(list_path);
  if (!in) throw MakeInputError(list_path, "cannot be opened");
  std::map<std::string, std::string> hashes;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string hash = line.substr(0, 64);
    std::size_t name_start = 64;
    while (name_start < line.size() && line[name_start] == ' ') ++name_start;
    if (name_start < line.size() && line[name_start] == '*') ++name_start;
    if (!IsLowerHex64(hash) || name_start == 64 || name_start >= line.size()) {
      throw MakeInputError(list_path + ":" + std::to_string(line_number),
                           "malformed line \"" + line +
                               "\"; expected \"<64 lowercase hex digits>  <relative path>\" as "
                               "written by sha256sum");
    }
    hashes[line.substr(name_start)] = hash;
  }
  return hashes;
}

// Rejects paths that could leave the assets folder; the list only holds plain relative paths.
void CheckRelativePath(const std::string& relative_path) {
  if (relative_path.empty()) throw MakeInputError("asset path", "is empty");
  const fs::path p(relative_path);
  bool escapes = p.is_absolute();
  for (const auto& part : p) escapes = escapes || part == "..";
  if (escapes) {
    throw MakeInputError(relative_path,
                         "asset path must be relative to the assets folder without \"..\" "
                         "(e.g. \"xfeat/xfeat_640x640.onnx\")");
  }
}

// What identifies a file version well enough to skip re-hashing: a rewrite changes the mtime
// or ctime (or the inode, for copy-and-rename), an append also the size.
struct FileStamp {
  dev_t device;
  ino_t inode;
  off_t size;
  long long mtime_ns;
  long long ctime_ns;
  bool operator==(const FileStamp& o) const {
    return std::tie(device, inode, size, mtime_ns, ctime_ns) ==
           std::tie(o.device, o.inode, o.size, o.mtime_ns, o.ctime_ns);
  }
};

struct HashedFile {
  FileStamp stamp;
  std::string sha256;
};

std::mutex g_cache_mutex;
std::map<std::string, HashedFile> g_verified;  // keyed by absolute path
std::size_t g_files_hashed = 0;

long long ToNanoseconds(const timespec& t) {
  return static_cast<long long>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

}  // namespace

std::string Sha256OfFile(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw MakeInputError(path, std::string("cannot be read (") + std::strerror(errno) + ")");
  }
  if (S_ISDIR(info.st_mode)) throw MakeInputError(path, "is a directory, expected a file");

  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw MakeInputError(path, std::string("cannot be opened (") + std::strerror(errno) + ")");
  }
  // Model files are a few MB; hash in fixed chunks so memory use does not grow with the file.
  detail::Sha256 hasher;
  std::vector<unsigned char> chunk(1 << 16);
  std::size_t got = 0;
  while ((got = std::fread(chunk.data(), 1, chunk.size(), file)) > 0)
    hasher.Update(chunk.data(), got);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed) throw MakeInputError(path, "read error while computing its sha256");
  return hasher.HexDigest();
}

namespace detail {

std::string LoadedObjectPath() {
  static const char anchor = 0;
  Dl_info info{};
  link_map* object = nullptr;
  if (::dladdr1(&anchor, &info, reinterpret_cast<void**>(&object), RTLD_DL_LINKMAP) != 0 &&
      object != nullptr && object->l_name != nullptr && object->l_name[0] != '\0') {
    return object->l_name;
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.string();
}

std::string InstalledAssetsDirFor(const std::string& binary_path) {
  const fs::path binary_dir = fs::absolute(binary_path).lexically_normal().parent_path();
  const fs::path share = fs::path("share") / "zeroreg" / "assets";
  for (fs::path dir = binary_dir;; dir = dir.parent_path()) {
    if (IsDirectory((dir / share).string())) return (dir / share).string();
    if (dir == dir.parent_path()) break;
  }
  // The conventional place, P/bin/../share, so that the "not found" message names it.
  return (binary_dir.parent_path() / share).string();
}

std::string ResolveAssetsDirFrom(const std::string& explicit_dir, const std::string& env_value,
                                 const std::string& repo_dir,
                                 const std::vector<std::string>& installed_dirs) {
  // A folder the user named is meant to be used: falling back to another one would load models
  // other than those asked for, silently.
  if (!explicit_dir.empty()) {
    if (IsDirectory(explicit_dir)) return explicit_dir;
    throw MakeInputError(explicit_dir,
                         "assets folder (--assets / assets_dir) does not exist or is not a "
                         "folder; expected the folder scripts/fetch-assets.sh fills (leave the "
                         "option out to use $ZEROREG_ASSETS, then <repo>/assets)");
  }
  std::vector<std::pair<std::string, std::string>> tried;  // (source, path)
  if (!env_value.empty()) tried.emplace_back("environment variable ZEROREG_ASSETS", env_value);
  tried.emplace_back("repository default", JoinPath(repo_dir, "assets"));
  for (const std::string& dir : installed_dirs) tried.emplace_back("installed share folder", dir);

  for (const auto& candidate : tried) {
    if (IsDirectory(candidate.second)) return candidate.second;
  }
  std::ostringstream message;
  message << "no assets folder found; tried, in order:";
  for (const auto& candidate : tried) {
    message << "\n  " << candidate.second << " (" << candidate.first << "): not a directory";
  }
  if (env_value.empty()) message << "\n  (ZEROREG_ASSETS is not set)";
  message << "\nTo fill <repo>/assets " << kFetchHint
          << " (or pass --dest DIR and point --assets / ZEROREG_ASSETS at DIR).";
  throw MakeInputError("assets folder", message.str());
}

std::string RequireAssetFrom(const std::string& assets_dir, const std::string& relative_path,
                             const std::string& repo_dir) {
  CheckRelativePath(relative_path);

  // The repo's list is authoritative; the copy fetch-assets.sh puts next to the assets serves
  // builds whose source tree is gone (e.g. an installed binary).
  const std::string repo_list = JoinPath(repo_dir, std::string("scripts/") + kListName);
  const std::string assets_list = JoinPath(assets_dir, kListName);
  std::string list_path;
  for (const std::string& candidate : {repo_list, assets_list}) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      list_path = candidate;
      break;
    }
  }
  if (list_path.empty()) {
    throw MakeInputError(relative_path, "cannot be verified: no sha256 list at " + repo_list +
                                            " or " + assets_list + "; " + kFetchHint +
                                            " (it copies the list into the assets folder)");
  }
  const auto hashes = ReadHashList(list_path);
  const auto expected_it = hashes.find(fs::path(relative_path).lexically_normal().string());
  if (expected_it == hashes.end()) {
    throw MakeInputError(relative_path, "not in the sha256 list " + list_path +
                                            "; model files must be listed there (add \"$(sha256sum "
                                            "FILE)\" relative to assets/) and fetched with "
                                            "bash scripts/fetch-assets.sh");
  }
  const std::string& expected = expected_it->second;

  const std::string full_path = JoinPath(assets_dir, relative_path);
  struct stat info {};
  if (::stat(full_path.c_str(), &info) != 0) {
    throw MakeInputError(full_path, std::string("missing; ") + kFetchHint);
  }
  if (!S_ISREG(info.st_mode)) {
    throw MakeInputError(full_path, std::string("is not a regular file; ") + kFetchHint);
  }
  const std::string actual = Sha256OfFileRemembered(full_path);
  if (actual != expected) {
    throw MakeInputError(full_path, "sha256 mismatch (expected " + expected + ", got " + actual +
                                        "): the file is corrupt or a different version; " +
                                        kFetchHint + " to replace it");
  }
  return full_path;
}

std::string Sha256OfFileRemembered(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) {
    return Sha256OfFile(path);  // which names the problem
  }
  const FileStamp stamp{info.st_dev, info.st_ino, info.st_size, ToNanoseconds(info.st_mtim),
                        ToNanoseconds(info.st_ctim)};
  std::error_code ec;
  std::string key = fs::absolute(path, ec).lexically_normal().string();
  if (ec) key = path;
  {
    std::lock_guard<std::mutex> lock(g_cache_mutex);
    const auto remembered = g_verified.find(key);
    if (remembered != g_verified.end() && remembered->second.stamp == stamp) {
      return remembered->second.sha256;
    }
  }
  // A file changed in the same clock tick as it was hashed keeps its stamp, so a file modified
  // in the last two seconds is hashed again next time instead of remembered (git's "racy" rule).
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  const bool settled = ToNanoseconds(now) - stamp.mtime_ns > 2'000'000'000LL;
  const std::string digest = Sha256OfFile(path);
  std::lock_guard<std::mutex> lock(g_cache_mutex);
  ++g_files_hashed;
  if (settled) g_verified[key] = HashedFile{stamp, digest};
  return digest;
}

std::size_t AssetFilesHashedForTesting() {
  std::lock_guard<std::mutex> lock(g_cache_mutex);
  return g_files_hashed;
}

}  // namespace detail

std::string ResolveAssetsDir(const std::string& explicit_dir) {
  const char* env = std::getenv("ZEROREG_ASSETS");
  std::vector<std::string> installed;
  const std::string binary = detail::LoadedObjectPath();
  if (!binary.empty()) installed.push_back(detail::InstalledAssetsDirFor(binary));
  if (installed.empty() || installed.front() != ZEROREG_INSTALL_ASSETS_DIR)
    installed.push_back(ZEROREG_INSTALL_ASSETS_DIR);
  return detail::ResolveAssetsDirFrom(explicit_dir, env != nullptr ? env : "", ZEROREG_REPO_DIR,
                                      installed);
}

std::string RequireAsset(const std::string& assets_dir, const std::string& relative_path) {
  return detail::RequireAssetFrom(assets_dir, relative_path, ZEROREG_REPO_DIR);
}

}  // namespace zeroreg
