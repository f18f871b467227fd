// glibc malloc settings for the zeroreg process (docs/SPEED.md, "Page faults and glibc's malloc").
// Plain C calls only: the functions run before libstdc++'s and every other library's initialisers.
#pragma once

namespace zeroreg::cli {

// The environment `envp` with glibc's malloc tunables added to GLIBC_TUNABLES (a key the user
// already set is kept as set) and ZEROREG_MALLOC_TUNING=applied; a new malloc'd array whose strings
// are envp's or new. nullptr when nothing is to change: ZEROREG_MALLOC_TUNING is set ("off", or
// "applied" by an earlier run), the user set every key, or memory ran out.
char** TunedEnvironment(char** envp);

}  // namespace zeroreg::cli
