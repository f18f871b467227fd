// Splitting a loop over threads without changing its result: the range [0, n) is cut into at most
// `threads` contiguous chunks, each run on its own thread (the first on the caller's). Callers
// write per-index results into their own slots and reduce them serially afterwards, in index
// order, so that floating-point sums do not depend on the thread count.
#pragma once

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace zeroreg {

// Calls body(begin, end) on disjoint chunks covering [0, n); returns when all are done. The first
// exception thrown by a chunk is rethrown here (after every thread has joined). A chunk gets at
// least `min_per_thread` items: the default suits cheap items (below a few thousand of them a
// thread costs more than it saves, ~50 us to start one); pass 1 for a few expensive ones.
template <typename Body>
void ParallelFor(size_t n, int threads, const Body& body, size_t min_per_thread = 1024) {
  const size_t chunks =
      std::max<size_t>(1, std::min<size_t>(static_cast<size_t>(std::max(1, threads)),
                                           n / std::max<size_t>(1, min_per_thread)));
  if (chunks <= 1) {
    body(size_t{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(chunks);
  std::vector<std::thread> workers;
  workers.reserve(chunks - 1);
  const auto run = [&](size_t c) {
    try {
      body(n * c / chunks, n * (c + 1) / chunks);
    } catch (...) {
      errors[c] = std::current_exception();
    }
  };
  for (size_t c = 1; c < chunks; ++c) workers.emplace_back(run, c);
  run(0);
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace zeroreg
