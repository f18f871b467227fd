#include "inference/graph_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "assets/assets_internal.hpp"
#include "assets/sha256.hpp"
#include "io/file_bytes.hpp"
#include "zeroreg/assets.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#define ZEROREG_GRAPH_CACHE_X86 1
#else
#define ZEROREG_GRAPH_CACHE_X86 0
#endif

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

std::string Environment(const char* name) {
  const char* value = std::getenv(name);
  return value == nullptr ? std::string() : std::string(value);
}

std::string Sha256OfString(const std::string& bytes) {
  detail::Sha256 hash;
  hash.Update(bytes);
  return hash.HexDigest();
}

// The first line of a small text file, or "" when it cannot be read.
std::string ReadFirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::atomic<unsigned> g_scratch_counter{0};

constexpr size_t kSecretBytes = 32;

// The per-user secret that signs the entries of `directory`: <directory>/.hmac-key-<uid>, 32
// random bytes, a regular file (not a link) of this user that nobody else may read or write.
// Anyone else who can write the directory can replace a graph and its check line, but cannot make
// a check line that verifies without this secret. With `create`, a missing secret is made (by one
// process: the file appears whole through link(2), which refuses to replace one another process
// made meanwhile). nullopt when there is none, or it is not trustworthy.
std::optional<std::string> CacheSecret(const fs::path& directory, bool create) {
  const fs::path path = directory / (".hmac-key-" + std::to_string(::geteuid()));
  const auto read_secret = [&]() -> std::optional<std::string> {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    struct stat info {};
    std::string secret(kSecretBytes, '\0');
    const bool trusted = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) &&
                         info.st_uid == ::geteuid() && (info.st_mode & 077) == 0 &&
                         info.st_size == static_cast<off_t>(kSecretBytes) &&
                         ::read(fd, &secret[0], kSecretBytes) == static_cast<ssize_t>(kSecretBytes);
    ::close(fd);
    if (!trusted) return std::nullopt;
    return secret;
  };
  if (std::optional<std::string> secret = read_secret()) return secret;
  std::error_code error;
  if (!create || fs::exists(fs::symlink_status(path, error))) return std::nullopt;
  std::string secret(kSecretBytes, '\0');
  {
    std::ifstream random("/dev/urandom", std::ios::binary);
    if (!random.read(&secret[0], kSecretBytes)) return std::nullopt;
  }
  const std::string scratch = path.string() + ".tmp-" + std::to_string(getpid()) + "-" +
                              std::to_string(g_scratch_counter++);
  const int fd =
      ::open(scratch.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) return std::nullopt;
  const bool written =
      ::write(fd, secret.data(), kSecretBytes) == static_cast<ssize_t>(kSecretBytes);
  ::close(fd);
  const bool linked = written && ::link(scratch.c_str(), path.c_str()) == 0;
  ::unlink(scratch.c_str());
  if (linked) return secret;
  return read_secret();  // another process made it first
}

// HMAC-SHA256 (RFC 2104) of `message` under `secret` (at most one block), as hex digits.
std::string HmacSha256Hex(const std::string& secret, const std::string& binding,
                          const std::vector<char>& message) {
  std::string block(64, '\0');
  std::copy(secret.begin(), secret.end(), block.begin());
  std::string inner_pad(block), outer_pad(block);
  for (char& c : inner_pad) c = static_cast<char>(c ^ 0x36);
  for (char& c : outer_pad) c = static_cast<char>(c ^ 0x5c);
  detail::Sha256 inner;
  inner.Update(inner_pad);
  inner.Update(binding);
  inner.Update(message.data(), message.size());
  const std::string inner_hex = inner.HexDigest();
  std::string inner_bytes;
  for (size_t i = 0; i + 1 < inner_hex.size(); i += 2) {
    inner_bytes.push_back(static_cast<char>(std::stoi(inner_hex.substr(i, 2), nullptr, 16)));
  }
  detail::Sha256 outer;
  outer.Update(outer_pad);
  outer.Update(inner_bytes);
  return outer.HexDigest();
}

// What a check line signs besides the graph: the entry's whole key (the verified model's sha256,
// the runtime version, the optimisation level, the CPU), so that a graph made for another model or
// runtime, copied under this entry's name with its check line, does not verify either.
std::string Binding(const GraphCacheEntry& entry) {
  return "zeroreg-graph-cache-1;" + entry.key + ";";
}

}  // namespace

std::optional<std::string> GraphCacheDirectory(const std::string& setting) {
  if (setting == "off") return std::nullopt;
  if (setting != "auto") return setting;
  std::string base = Environment("ZEROREG_CACHE_DIR");
  if (base.empty() && !Environment("XDG_CACHE_HOME").empty()) {
    base = Environment("XDG_CACHE_HOME") + "/zeroreg";
  }
  if (base.empty() && !Environment("HOME").empty()) base = Environment("HOME") + "/.cache/zeroreg";
  if (base.empty()) return std::nullopt;
  return base + "/onnxruntime-graphs";
}

std::string CpuSignature() {
#if ZEROREG_GRAPH_CACHE_X86
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(0, &eax, &ebx, &ecx, &edx)) return "unknown-cpu";
  const unsigned max_leaf = eax;
  char vendor[13] = {};
  const unsigned words[3] = {ebx, edx, ecx};  // "GenuineIntel" is spelled in this order
  for (int i = 0; i < 12; ++i)
    vendor[i] = static_cast<char>((words[i / 4] >> (8 * (i % 4))) & 0xff);
  std::ostringstream out;
  out << vendor << std::hex;
  __get_cpuid(1, &eax, &ebx, &ecx, &edx);
  // EAX: stepping, model, family; ECX / EDX: SSE3 .. AVX, FMA, F16C, OSXSAVE, ... (EBX holds the
  // APIC id of the core this thread runs on: left out, or the key would change between cores).
  out << ":1:" << eax << "," << ecx << "," << edx;
  const bool osxsave = (ecx & (1U << 27)) != 0;
  if (max_leaf >= 7) {
    __get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx);  // AVX2, AVX-512*, VNNI, AMX, ...
    out << ":7:" << ebx << "," << ecx << "," << edx;
  }
  if (osxsave) {
    // XCR0: which register states (AVX, AVX-512, AMX) the OS saves, i.e. what may really run.
    unsigned xcr0_low = 0, xcr0_high = 0;
    __asm__ volatile("xgetbv" : "=a"(xcr0_low), "=d"(xcr0_high) : "c"(0));
    out << ":xcr0:" << xcr0_low << "," << xcr0_high;
  }
  return out.str();
#else
  return "unknown-cpu";
#endif
}

GraphCacheEntry GraphCacheEntryFor(const std::string& directory, const std::string& model_path,
                                   const std::string& runtime_version) {
  // ORT_ENABLE_ALL is the level of every session zeroreg creates (src/inference/onnx_model.cpp);
  // it is in the key so that a change of level can never read graphs made at the old one.
  const std::string key = Sha256OfString("model=" + detail::Sha256OfFileRemembered(model_path) +
                                         ";runtime=onnxruntime-" + runtime_version +
                                         ";level=all;cpu=" + CpuSignature());
  const std::string name = fs::path(model_path).stem().string() + "-" + key.substr(0, 16);
  GraphCacheEntry entry;
  entry.graph_path = (fs::path(directory) / (name + ".onnx")).string();
  entry.digest_path = entry.graph_path + ".hmac";
  entry.key = key;
  return entry;
}

std::optional<std::vector<char>> ReadValidGraph(const GraphCacheEntry& entry) {
  const std::string expected = ReadFirstLine(entry.digest_path);
  if (expected.size() != 64) return std::nullopt;
  const std::optional<std::string> secret =
      CacheSecret(fs::path(entry.graph_path).parent_path(), /*create=*/false);
  if (!secret) return std::nullopt;
  std::ifstream in(entry.graph_path, std::ios::binary);
  if (!in) return std::nullopt;
  std::optional<std::vector<char>> bytes = ReadAllBytes<char>(in);
  if (!bytes) return std::nullopt;
  if (HmacSha256Hex(*secret, Binding(entry), *bytes) != expected) return std::nullopt;
  return bytes;
}

bool GraphCacheEntryValid(const GraphCacheEntry& entry) {
  return ReadValidGraph(entry).has_value();
}

std::optional<std::string> GraphCacheScratchPath(const GraphCacheEntry& entry) {
  std::error_code error;
  const fs::path directory = fs::path(entry.graph_path).parent_path();
  fs::create_directories(directory, error);
  if (error || access(directory.c_str(), W_OK) != 0) return std::nullopt;
  return entry.graph_path + ".tmp-" + std::to_string(getpid()) + "-" +
         std::to_string(g_scratch_counter++);
}

bool CommitGraphCacheEntry(const GraphCacheEntry& entry, const std::string& scratch_path) {
  std::error_code error;
  const auto discard = [&](const std::string& path) {
    fs::remove(path, error);
    return false;
  };
  std::optional<std::vector<char>> bytes;
  {
    std::ifstream in(scratch_path, std::ios::binary);
    if (in) bytes = ReadAllBytes<char>(in);
  }
  if (!bytes || bytes->empty()) return discard(scratch_path);  // the runtime did not write it
  const std::optional<std::string> secret =
      CacheSecret(fs::path(entry.graph_path).parent_path(), /*create=*/true);
  if (!secret) return discard(scratch_path);
  const std::string digest = HmacSha256Hex(*secret, Binding(entry), *bytes);
  fs::rename(scratch_path, entry.graph_path, error);
  if (error) return discard(scratch_path);
  const std::string digest_scratch = scratch_path + ".sha256";
  {
    std::ofstream out(digest_scratch, std::ios::trunc);
    out << digest << "\n";
    if (!out.flush()) return discard(digest_scratch);
  }
  fs::rename(digest_scratch, entry.digest_path, error);
  if (error) return discard(digest_scratch);
  return true;
}

}  // namespace zeroreg
