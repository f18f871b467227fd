// Why these settings: a registration allocates and frees a few hundred MB of short-lived buffers
// (network activations, point clouds, k-d trees). With glibc's defaults every block above the
// dynamic mmap threshold is a fresh mmap, and the heap grows in 128 KiB steps, all on 4 KiB pages:
// each run of a model page-faults its working set in again. On virtual machines a page fault costs
// microseconds, and faults were a large share of a frame pair's process time (docs/SPEED.md, "Page
// faults and glibc's malloc"). The settings
// keep blocks under 32 MiB on the heap (reused after free, not unmapped), grow the heap 64 MiB at a
// time, and ask the kernel for transparent huge pages on malloc's memory (with THP in its common
// "madvise" mode the kernel gives them only where asked). glibc reads GLIBC_TUNABLES once, when a
// process starts, so they must be in the environment before the program's first instruction: the
// `zeroreg` launcher (apps/launcher/) puts them there, and zeroreg-core run directly re-executes
// itself with them (apps/malloc_tuning.cpp). Where memory is never changes what is computed.
#include "tuned_environment.hpp"

#include <cstdlib>
#include <cstring>

namespace zeroreg::cli {
namespace {

constexpr const char* kSwitch = "ZEROREG_MALLOC_TUNING";
constexpr const char* kTunables = "GLIBC_TUNABLES";
// key, value; glibc's manual, "Memory Allocation Tunables".
constexpr const char* kSettings[][2] = {
    {"glibc.malloc.hugetlb", "1"},                // madvise(MADV_HUGEPAGE) on malloc's memory
    {"glibc.malloc.mmap_threshold", "33554432"},  // blocks < 32 MiB from the heap, reused
    {"glibc.malloc.top_pad", "67108864"},         // grow the heap 64 MiB at a time
    // At most two heaps (glibc's default: 8 per core). Each thread that allocates otherwise gets
    // a heap of its own (ONNX Runtime's pool, the two scans' perception, eval's runners), and a
    // long-lived block (a prepared scan that eval keeps) pins free space around it in every one,
    // and eval's peak memory grows with the heaps (docs/SPEED.md, `arena_max`). The
    // heavy allocating work runs at most two ways at once (RunBoth), so two heaps cost no
    // measurable lock wait (docs/SPEED.md).
    {"glibc.malloc.arena_max", "2"},
};

bool IsVariable(const char* entry, const char* name) {
  const std::size_t n = std::strlen(name);
  return std::strncmp(entry, name, n) == 0 && entry[n] == '=';
}

// The value of `name` in envp, or nullptr.
const char* Find(char** envp, const char* name) {
  for (char** e = envp; e && *e; ++e) {
    if (IsVariable(*e, name)) return *e + std::strlen(name) + 1;
  }
  return nullptr;
}

}  // namespace

char** TunedEnvironment(char** envp) {
  if (Find(envp, kSwitch) != nullptr) return nullptr;
  const char* user = Find(envp, kTunables);
  // "GLIBC_TUNABLES=" + the user's + ":key=value" per setting missing from it.
  std::size_t length = std::strlen(kTunables) + 2 + (user ? std::strlen(user) : 0);
  for (const auto& kv : kSettings) length += std::strlen(kv[0]) + std::strlen(kv[1]) + 2;
  char* tunables = static_cast<char*>(std::malloc(length));
  if (tunables == nullptr) return nullptr;
  std::strcpy(tunables, kTunables);
  std::strcat(tunables, "=");
  if (user) std::strcat(tunables, user);
  bool added = false;
  for (const auto& kv : kSettings) {
    if (user && std::strstr(user, kv[0])) continue;
    if (tunables[std::strlen(kTunables) + 1] != '\0') std::strcat(tunables, ":");
    std::strcat(tunables, kv[0]);
    std::strcat(tunables, "=");
    std::strcat(tunables, kv[1]);
    added = true;
  }
  std::size_t count = 0;
  while (envp && envp[count]) ++count;
  char** env = added ? static_cast<char**>(std::malloc((count + 3) * sizeof(char*))) : nullptr;
  if (env == nullptr) {
    std::free(tunables);
    return nullptr;
  }
  // Everything but the old GLIBC_TUNABLES, then the new one and the marker that stops a later
  // run from doing this again.
  static char marker[] = "ZEROREG_MALLOC_TUNING=applied";
  std::size_t k = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!IsVariable(envp[i], kTunables)) env[k++] = envp[i];
  }
  env[k++] = tunables;
  env[k++] = marker;
  env[k] = nullptr;
  return env;
}

}  // namespace zeroreg::cli
