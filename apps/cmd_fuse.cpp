#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "fuse/fuse.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg::cli {
namespace {

// "A-B" (inclusive) or "a,b,c"; ids must exist in the dataset.
std::vector<int> ParseFrames(const std::string& text, const Dataset& dataset) {
  std::vector<int> ids;
  try {
    const size_t dash = text.find('-');
    if (dash != std::string::npos && dash > 0) {
      const int first = std::stoi(text.substr(0, dash)), last = std::stoi(text.substr(dash + 1));
      if (last < first) throw std::invalid_argument("range end before start");
      for (int i = first; i <= last; ++i) ids.push_back(i);
    } else {
      size_t start = 0;
      while (start < text.size()) {
        const size_t comma = text.find(',', start);
        ids.push_back(std::stoi(text.substr(start, comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
  } catch (const std::exception&) {
    throw MakeInputError("--frames " + text, "expected a range A-B (inclusive) or a list a,b,c");
  }
  const std::vector<int> available = dataset.FrameIds();
  for (int id : ids) {
    if (!std::binary_search(available.begin(), available.end(), id)) {
      throw MakeInputError("--frames " + text,
                           "frame " + std::to_string(id) + " is not in " + dataset.root());
    }
  }
  return ids;
}

struct FuseOptions {
  std::string dataset, frames, out;
  double depth_scale = 0.0;
  FuseConfig config;
};

}  // namespace

Runner AddFuseCommand(CLI::App& app) {
  auto o = std::make_shared<FuseOptions>();
  app.add_option("--dataset,-d", o->dataset,
                 "RGB-D sequence folder (3DMatch, TUM or ScanNet layout)")
      ->required();
  app.add_option("--frames,-f", o->frames,
                 "frames to fuse: A-B inclusive or a,b,c (3DMatch "
                 "fragment k is 50k-(50k+49))")
      ->required();
  app.add_option("--out,-o", o->out, "fragment folder to write (scan.json, cloud.ply, views)")
      ->required();
  app.add_option("--views", o->config.num_views, "views kept with the fragment (default 3)");
  app.add_option("--voxel", o->config.voxel_length_m, "TSDF voxel size in metres (default 0.01)");
  app.add_option("--depth-scale", o->depth_scale, "raw depth units per metre (default: layout's)");
  return [o]() {
    DatasetOptions options;
    options.depth_scale = o->depth_scale;
    const auto dataset = OpenDataset(o->dataset, options);
    const std::vector<int> frames = ParseFrames(o->frames, *dataset);
    const bool built = FuseFragment(*dataset, frames, o->config, o->out, [](int done, int total) {
      std::fprintf(stderr, "\rfusing frame %d/%d", done, total);
      if (done == total) std::fprintf(stderr, "\n");
    });
    std::printf("%s %s (%zu frames, %d views)\n", built ? "fused" : "cached, reused",
                o->out.c_str(), frames.size(), o->config.num_views);
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
