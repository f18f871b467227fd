// Accumulates wall time per named stage, in first-seen order.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

class StageTimer {
 public:
  // Adds the time since the last call to Mark (or construction) to `stage`.
  void Mark(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    Add(stage, std::chrono::duration<double, std::milli>(now - last_).count());
    last_ = now;
  }
  void Restart() { last_ = std::chrono::steady_clock::now(); }
  void Add(const std::string& stage, double ms) {
    for (StageTime& t : times_) {
      if (t.stage == stage) {
        t.ms += ms;
        return;
      }
    }
    times_.push_back({stage, ms});
  }
  const std::vector<StageTime>& times() const { return times_; }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
  std::vector<StageTime> times_;
};

}  // namespace zeroreg
