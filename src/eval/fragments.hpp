// 3DMatch fragments rebuilt from RGB-D on demand: fragment k = TSDF fusion of frames
// 50k .. 50k+49 in the camera frame of frame 50k (FuseFragment, cached on disk). Only the
// fragments that the selected, not yet finished pairs need are fused.
#pragma once

#include <string>
#include <vector>

#include "fuse/fuse.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

struct FragmentSource {
  const Dataset* dataset = nullptr;
  int frames_per_fragment = 50;  // 3DMatch
  FuseConfig fuse;               // fuse.num_views = the paper's "views" (Table 5)
  std::string cache_dir = "cache/fragments";
  std::string scene = "7-scenes-redkitchen";
  double depth_scale = 0.0;  // --depth-scale as given (0 = the layout's), for the cache folder

  // <cache_dir>/<scene>/fragment-k with the default fusion settings; otherwise
  // <cache_dir>/<scene>/<tag>/fragment-k, tag e.g. "views-1", "voxel-40mm" or "depth-scale-5000",
  // so that Table 5's three settings (or a coarse CI fusion) do not evict each other's cache. (The
  // fragment's fuse.json decides reuse: it holds every input, see FuseFragment.)
  std::string Dir(int k) const;
  std::string ScanJson(int k) const { return Dir(k) + "/scan.json"; }
};

// Fuses (or reuses) each fragment of `ks`, using up to `jobs` threads. A per-fragment lock file
// (flock) makes concurrent runs on one machine (GNU parallel shards) wait for each other instead
// of fusing the same folder twice. Returns how many were (re)built.
int EnsureFragments(const FragmentSource& source, const std::vector<int>& ks, int jobs,
                    bool progress);

}  // namespace zeroreg
