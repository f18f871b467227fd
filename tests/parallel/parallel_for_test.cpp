#include "parallel/parallel_for.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace zeroreg {
namespace {

TEST(ParallelFor, EveryIndexExactlyOnceForAnyThreadCount) {
  for (size_t n : {size_t{0}, size_t{1}, size_t{1023}, size_t{5000}, size_t{100003}}) {
    for (int threads : {0, 1, 2, 3, 7}) {
      std::vector<int> hits(n, 0);
      std::atomic<int> chunks{0};
      ParallelFor(n, threads, [&](size_t begin, size_t end) {
        ++chunks;
        for (size_t i = begin; i < end; ++i) ++hits[i];
      });
      for (size_t i = 0; i < n; ++i) {
        ASSERT_EQ(hits[i], 1) << n << " " << threads << " " << i;
      }
      EXPECT_LE(chunks.load(), std::max(1, threads));
      if (n >= 100000 && threads >= 2) {
        EXPECT_EQ(chunks.load(), threads);  // really split
      }
    }
  }
}

TEST(ParallelFor, AnExceptionOfAChunkReachesTheCaller) {
  EXPECT_THROW(ParallelFor(10000, 2,
                           [](size_t begin, size_t) {
                             if (begin > 0) throw std::runtime_error("second chunk");
                           }),
               std::runtime_error);
}

}  // namespace
}  // namespace zeroreg
