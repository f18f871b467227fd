// zeroreg-core run directly (not through the `zeroreg` launcher, apps/launcher/): re-execute this
// program with glibc's malloc tunables in its environment (apps/tuned_environment.cpp says why).
// A function in .preinit_array runs before any shared library's initialiser (Open3D, OpenCV, ONNX
// Runtime), so the first run costs only the dynamic loader's mapping and relocation of the
// libraries; the launcher, which links nothing but libc, avoids even that.
// ZEROREG_MALLOC_TUNING=off turns it off.
#include <unistd.h>

#include <climits>
#include <cstdlib>

#include "tuned_environment.hpp"

namespace {

void TuneMallocAndReexecute(int /*argc*/, char** argv, char** envp) {
  char** env = zeroreg::cli::TunedEnvironment(envp);
  if (env == nullptr) return;
  // The program's own file: readlink rather than executing /proc/self/exe, so that a run under
  // valgrind (which reports the client's path here) executes the client, not the tool.
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n > 0) {
    self[n] = '\0';
    execve(self, argv, env);
  }
  // Not executed (no permission, file replaced): go on untuned, with the same results.
  std::free(env);
}

}  // namespace

// Executables only: the dynamic loader calls these before any shared library's initialisers.
__attribute__((section(".preinit_array"),
               used)) void (*const zeroreg_tune_malloc)(int, char**,
                                                        char**) = &TuneMallocAndReexecute;
