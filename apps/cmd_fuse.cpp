#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "config_options.hpp"
#include "fuse/fuse.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg::cli {
namespace {

// "A-B" (inclusive) or "a,b,c"; ids must exist in the dataset. A range is checked id by id as it
// is expanded, so "0-999999999" stops at the first missing frame instead of allocating gigabytes.
std::vector<int> ParseFrames(const std::string& text, const Dataset& dataset) {
  const std::vector<int> available = dataset.FrameIds();
  std::vector<int> ids;
  auto add = [&](long long id) {
    if (!std::binary_search(available.begin(), available.end(), id)) {
      throw MakeInputError("--frames " + text,
                           "frame " + std::to_string(id) + " is not in " + dataset.root());
    }
    ids.push_back(static_cast<int>(id));
  };
  std::vector<long long> bounds;
  const size_t dash = text.find('-');
  const bool range = dash != std::string::npos && dash > 0;
  try {
    if (range) {
      size_t used_first = 0, used_last = 0;
      const std::string first = text.substr(0, dash), last = text.substr(dash + 1);
      bounds = {std::stoll(first, &used_first), std::stoll(last, &used_last)};
      if (used_first != first.size() || used_last != last.size() || bounds[1] < bounds[0]) {
        throw std::invalid_argument("range");
      }
    } else {
      for (size_t start = 0; start < text.size();) {
        const size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma - start);
        size_t used = 0;
        bounds.push_back(std::stoll(item, &used));
        if (used != item.size()) throw std::invalid_argument("list");
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
  } catch (const std::exception&) {
    throw MakeInputError("--frames " + text, "expected a range A-B (inclusive) or a list a,b,c");
  }
  if (bounds.empty()) {
    throw MakeInputError("--frames " + text, "expected a range A-B (inclusive) or a list a,b,c");
  }
  if (range) {
    for (long long id = bounds[0]; id <= bounds[1]; ++id) add(id);
  } else {
    for (long long id : bounds) add(id);
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
  app.add_option("--views", o->config.num_views, "views kept with the fragment (default 3)")
      ->check(AtLeast(1, /*integer=*/true));
  app.add_option("--voxel", o->config.voxel_length_m,
                 "TSDF voxel size in metres (default 0.01; at least 0.002, see "
                 "ZEROREG_MIN_FUSE_VOXEL_M in docs/FORMATS.md)");
  app.add_option("--depth-scale", o->depth_scale, "raw depth units per metre (default: layout's)");
  return [o]() {
    DatasetOptions options;
    options.depth_scale = o->depth_scale;
    CheckFuseConfig(o->config);  // before the dataset is read
    std::error_code ec;
    if (std::filesystem::exists(o->out, ec) && !std::filesystem::is_directory(o->out, ec)) {
      throw MakeInputError("--out " + o->out,
                           "exists and is not a folder; expected a folder for the fragment "
                           "(scan.json, cloud.ply, views) or a new name");
    }
    const auto dataset = OpenDataset(o->dataset, options);
    const std::vector<int> frames = ParseFrames(o->frames, *dataset);
    const bool built = FuseFragment(*dataset, frames, o->config, o->out, [](int done, int total) {
      std::fprintf(stderr, "\rfusing frame %d/%d", done, total);
      if (done == total) std::fprintf(stderr, "\n");
    });
    // Fewer frames than --views keeps every frame as a view.
    const size_t views = ChooseViewFrames(frames, o->config.num_views).size();
    std::printf("%s %s (%zu frames, %zu views)\n", built ? "fused" : "cached, reused",
                o->out.c_str(), frames.size(), views);
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
