// The prepared scans of `zeroreg eval`: a scan that is in several pairs of a list (every
// frame of a sequence list is in about two) is read and perceived once, and the prepared scan is
// reused by every later pair that names it, by any runner thread.
//
// Bounded two ways, least recently used first out: at most `max_scans` prepared scans and at most
// `max_bytes` of what they hold (PreparedScan::MemoryBytes: images, features, masks, clouds),
// checked at each insertion; a scan that grows afterwards (its turned images' features) can take
// the cache over `max_bytes` until the next insertion re-reads the sizes. The scan being
// returned is never evicted by its own insertion. Thread-safe; when two threads ask for
// the same key at once, one prepares it and the other waits for that.
#pragma once

#include <cstddef>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <mutex>
#include <string>

#include "zeroreg/register.hpp"

namespace zeroreg {

class PreparedScanCache {
 public:
  // A frame pair's scans are 10-20 MiB prepared (640x480 RGB-D, 4096 XFeat keypoints, ~10 masks):
  // the defaults keep a sequence list's sliding window (gap 60 at stride 10 = 7 frames) many
  // times over while staying far below the 1 GB a process may use (docs/SPEED.md).
  static constexpr std::size_t kDefaultMaxScans = 32;
  static constexpr std::size_t kDefaultMaxBytes = std::size_t{512} << 20;

  explicit PreparedScanCache(std::size_t max_scans = kDefaultMaxScans,
                             std::size_t max_bytes = kDefaultMaxBytes);

  // The prepared scan of `key`, made by `prepare` when it is not cached. An exception of
  // `prepare` reaches every caller waiting for that key, and the key is not cached.
  PreparedScan Get(const std::string& key, const std::function<PreparedScan()>& prepare);

  struct Stats {
    std::size_t hits = 0, misses = 0, evictions = 0;
    // held now; bytes as of the last insertion (a scan grows when its turned images' features
    // are first made, PreparedScan::MemoryBytes, and is counted so at the next insertion)
    std::size_t scans = 0, bytes = 0;
  };
  Stats stats() const;

 private:
  struct Entry {
    std::shared_future<PreparedScan> value;
    std::list<std::string>::iterator position;  // in lru_
    std::size_t bytes = 0;                      // 0 while being prepared
  };
  void EvictLocked(const std::string& keep);

  std::size_t max_scans_, max_bytes_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::list<std::string> lru_;  // most recently used first
  Stats stats_;
};

}  // namespace zeroreg
