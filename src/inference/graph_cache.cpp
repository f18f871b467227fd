#include "inference/graph_cache.hpp"

#include <unistd.h>

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
  entry.digest_path = entry.graph_path + ".sha256";
  return entry;
}

std::optional<std::vector<char>> ReadValidGraph(const GraphCacheEntry& entry) {
  const std::string expected = ReadFirstLine(entry.digest_path);
  if (expected.size() != 64) return std::nullopt;
  std::ifstream in(entry.graph_path, std::ios::binary);
  if (!in) return std::nullopt;
  std::optional<std::vector<char>> bytes = ReadAllBytes<char>(in);
  if (!bytes) return std::nullopt;
  detail::Sha256 hash;
  hash.Update(bytes->data(), bytes->size());
  if (hash.HexDigest() != expected) return std::nullopt;
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
  std::string digest;
  try {
    digest = Sha256OfFile(scratch_path);
  } catch (const std::exception&) {
    return discard(scratch_path);  // the runtime did not write it
  }
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
