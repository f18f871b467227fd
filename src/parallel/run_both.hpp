// Two independent pieces of work, on two threads or one after the other, with the same error
// reported either way.
#pragma once

#include <exception>
#include <future>

namespace zeroreg {

// Runs `a` on a new thread and `b` on this one when `parallel`, else `a` then `b`. An exception of
// `a` is rethrown first either way (after both finished), so the error reported does not depend
// on the thread count.
template <typename A, typename B>
void RunBoth(bool parallel, const A& a, const B& b) {
  if (!parallel) {
    a();
    b();
    return;
  }
  std::future<void> pending = std::async(std::launch::async, a);
  std::exception_ptr b_error;
  try {
    b();
  } catch (...) {
    b_error = std::current_exception();
  }
  pending.get();
  if (b_error) std::rethrow_exception(b_error);
}

}  // namespace zeroreg
