#include "eval/fragments.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include "eval/runner.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace fs = std::filesystem;
namespace {

// Holds an exclusive flock on `path` for its lifetime.
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT, 0644)) {
    if (fd_ < 0) throw MakeInputError(path, "cannot create the fragment lock file");
    while (::flock(fd_, LOCK_EX) != 0) {
      if (errno != EINTR) throw MakeInputError(path, "cannot lock the fragment lock file");
    }
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

}  // namespace

std::string FragmentSource::Dir(int k) const {
  fs::path dir = fs::path(cache_dir) / scene;
  const FuseConfig defaults;
  std::string tag;
  if (fuse.num_views != defaults.num_views) tag = "views-" + std::to_string(fuse.num_views);
  if (fuse.voxel_length_m != defaults.voxel_length_m) {
    char voxel[32];
    std::snprintf(voxel, sizeof(voxel), "voxel-%gmm", fuse.voxel_length_m * 1000.0);
    tag += (tag.empty() ? "" : "-") + std::string(voxel);
  }
  if (depth_scale != 0.0) {
    char scale[48];
    std::snprintf(scale, sizeof(scale), "depth-scale-%g", depth_scale);
    tag += (tag.empty() ? "" : "-") + std::string(scale);
  }
  if (!tag.empty()) dir /= tag;
  return (dir / ("fragment-" + std::to_string(k))).string();
}

int EnsureFragments(const FragmentSource& source, const std::vector<int>& ks, int jobs,
                    bool progress) {
  if (ks.empty()) return 0;
  if (source.dataset == nullptr) throw std::logic_error("EnsureFragments: no dataset");
  ProgressBar bar("fusing fragments", static_cast<int>(ks.size()), progress);
  std::atomic<size_t> next{0};
  std::atomic<int> built{0};
  std::mutex error_mutex;
  std::string first_error;
  auto worker = [&]() {
    for (size_t n = next++; n < ks.size(); n = next++) {
      try {
        const int k = ks[n];
        std::vector<int> frames;
        for (int f = 0; f < source.frames_per_fragment; ++f) {
          frames.push_back(k * source.frames_per_fragment + f);
        }
        const std::string dir = source.Dir(k);
        fs::create_directories(fs::path(dir).parent_path());
        const FileLock lock(dir + ".lock");
        if (FuseFragment(*source.dataset, frames, source.fuse, dir)) ++built;
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> guard(error_mutex);
        if (first_error.empty()) first_error = e.what();
      }
      bar.Advance();
    }
  };
  std::vector<std::thread> threads;
  const int n_threads = std::max(1, std::min<int>(jobs, static_cast<int>(ks.size())));
  for (int t = 1; t < n_threads; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  bar.Finish();
  if (!first_error.empty()) throw InputError(first_error);
  return built;
}

}  // namespace zeroreg
