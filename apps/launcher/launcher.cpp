// `zeroreg`: the command users run. It links nothing but libc and executes zeroreg-core (the
// program with the pipeline, installed beside it) with glibc's malloc tunables in its environment:
// glibc reads them only when a process starts (apps/tuned_environment.cpp says why they matter;
// docs/SPEED.md measures it). Arguments, exit code, input and output are zeroreg-core's own.
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>

#include "tuned_environment.hpp"

extern char** environ;

int main(int /*argc*/, char** argv) {
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0) {
    std::fprintf(stderr, "zeroreg: cannot read /proc/self/exe (%s); expected Linux's /proc\n",
                 std::strerror(errno));
    return 3;
  }
  self[n] = '\0';
  char* slash = std::strrchr(self, '/');
  static const char kCore[] = "zeroreg-core";
  if (slash == nullptr || (slash - self) + sizeof(kCore) + 1 > sizeof(self)) return 3;
  std::strcpy(slash + 1, kCore);
  char** env = zeroreg::cli::TunedEnvironment(environ);
  execve(self, argv, env != nullptr ? env : environ);
  std::fprintf(stderr,
               "zeroreg: cannot run %s: %s; expected the zeroreg-core program installed beside "
               "zeroreg (cmake --install puts both in bin/)\n",
               self, std::strerror(errno));
  return 3;
}
