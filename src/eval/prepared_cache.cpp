#include "eval/prepared_cache.hpp"

#include <algorithm>

namespace zeroreg {

PreparedScanCache::PreparedScanCache(std::size_t max_scans, std::size_t max_bytes)
    : max_scans_(std::max<std::size_t>(1, max_scans)), max_bytes_(max_bytes) {}

PreparedScan PreparedScanCache::Get(const std::string& key,
                                    const std::function<PreparedScan()>& prepare) {
  std::promise<PreparedScan> promise;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto it = entries_.find(key);
    if (it != entries_.end()) {
      ++stats_.hits;
      lru_.splice(lru_.begin(), lru_, it->second.position);
      const std::shared_future<PreparedScan> value = it->second.value;
      lock.unlock();  // another thread may still be preparing it: wait outside the lock
      return value.get();
    }
    ++stats_.misses;
    lru_.push_front(key);
    entries_[key] = Entry{promise.get_future().share(), lru_.begin(), 0};
  }
  PreparedScan prepared;
  try {
    prepared = prepare();
  } catch (...) {
    promise.set_exception(std::current_exception());
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = entries_.find(key);
    if (it != entries_.end()) {
      lru_.erase(it->second.position);
      entries_.erase(it);
    }
    throw;
  }
  promise.set_value(prepared);
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = entries_.find(key);
  if (it != entries_.end()) {  // (may have been evicted meanwhile; then it is just not kept)
    it->second.bytes = prepared.MemoryBytes();
    stats_.bytes += it->second.bytes;
  }
  EvictLocked(key);
  return prepared;
}

void PreparedScanCache::EvictLocked(const std::string& keep) {
  // A prepared scan grows after it is cached when it is first the source of a pair that turns
  // its images (PreparedScan::MemoryBytes): the budget counts what each holds now.
  for (auto& key_entry : entries_) {
    Entry& entry = key_entry.second;
    // bytes == 0: still being prepared (or just failed); its preparer counts it.
    if (entry.bytes == 0) continue;
    const std::size_t now = entry.value.get().MemoryBytes();  // ready: bytes are set after it
    stats_.bytes = stats_.bytes - entry.bytes + now;
    entry.bytes = now;
  }
  while (!lru_.empty() && (entries_.size() > max_scans_ || stats_.bytes > max_bytes_)) {
    // The least recently used entry other than `keep` goes.
    auto victim = std::prev(lru_.end());
    if (*victim == keep) {
      if (victim == lru_.begin()) break;  // only `keep` is left
      victim = std::prev(victim);
    }
    const auto it = entries_.find(*victim);
    stats_.bytes -= it->second.bytes;
    ++stats_.evictions;
    entries_.erase(it);
    lru_.erase(victim);
  }
}

PreparedScanCache::Stats PreparedScanCache::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Stats s = stats_;
  s.scans = entries_.size();
  return s;
}

}  // namespace zeroreg
