#include <cstdio>
#include <cstdlib>
#include <optional>

#include "commands.hpp"
#include "config_options.hpp"
#include "estimate/depth_noise.hpp"
#include "features/xfeat_extractor.hpp"
#include "io/text_parsing.hpp"
#include "open3d_module/open3d_module.hpp"
#include "segment/segmenter.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg::cli {
namespace {

struct InfoOptions {
  std::string scan;
  ConfigOptions config;
};

}  // namespace

Runner AddInfoCommand(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  app.add_option("--scan", o->scan, "also describe this scan (same forms as register --source)");
  AddConfigOptions(app, &o->config);
  return [o]() {
    const PipelineConfig config = BuildConfig(o->config);
    std::printf("effective config:\n%s\n", detail::DumpJson(ConfigToJson(config), 2).c_str());
    const std::string assets = ResolveAssetsDir(config.assets_dir);
    std::printf("assets: %s\n", assets.c_str());
    // What the launcher (apps/launcher/) or zeroreg-core's own re-execution set up.
    const char* tuning = std::getenv("ZEROREG_MALLOC_TUNING");
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    std::printf("malloc tuning: %s (GLIBC_TUNABLES=%s)\n", tuning ? tuning : "not applied",
                tunables ? tunables : "");
    // Loaded here only to say where it is; a registration loads it only when it needs it.
    try {
      std::printf("open3d module: %s (loads; needed for FPFH, point cloud files, fusion)\n",
                  open3d_module::LoadedModulePath().c_str());
    } catch (const InputError& e) {
      std::printf("open3d module: NOT LOADABLE: %s\n", e.what());
    }
    for (const std::string& file : {XFeatExtractor::ModelFile(config.features, config.inference),
                                    std::string("yolox_nano_coco/yolox_nano.onnx")}) {
      std::printf("  %s: %s (sha256 ok)\n", file.c_str(), RequireAsset(assets, file).c_str());
    }
    if (!o->scan.empty()) {
      const Scan scan = LoadScan(o->scan);
      std::printf("scan %s: %zu view(s), %zu points, ground truth %s\n", scan.name.c_str(),
                  scan.views.size(), scan.points.size(), scan.T_world_scan_gt ? "yes" : "no");
      for (const View& v : scan.views) {
        const double valid = cv::countNonZero(v.depth > 0) * 100.0 / v.depth.total();
        std::printf("  view %s: %dx%d, fx %.1f fy %.1f cx %.1f cy %.1f, valid depth %.1f%%",
                    v.name.c_str(), v.color.cols, v.color.rows, v.intrinsics.fx, v.intrinsics.fy,
                    v.intrinsics.cx, v.intrinsics.cy, valid);
        // What the noise floors of lifting and segmentation will use (docs/CONFIG.md, "Depth
        // noise").
        if (const std::optional<double> a = MeasureDepthNoiseAt1m(v)) {
          std::printf(", depth noise %.2f mm at 1 m", *a * 1000.0);
        } else {
          std::printf(", depth noise not measurable");
        }
        // Missing depth in gaps thinner than the segmenter's hole width is a hole in the
        // sensor's sampling, not an object's outline (docs/PERCEPTION.md, "Thin holes are not
        // depth edges"): a depth map warped from a lower-resolution sensor shows many.
        const cv::Mat missing_mask = detail::MissingDepth(v.depth);
        const int missing = cv::countNonZero(missing_mask);
        if (missing > 0) {
          const int width = config.segmenter.min_hole_width_px;
          const int wide = cv::countNonZero(detail::WideHoles(missing_mask, width));
          std::printf(", %.1f%% of the missing depth in gaps thinner than %d px",
                      (missing - wide) * 100.0 / missing, width);
        }
        std::printf("\n");
      }
      // ICP's auto grid decides on the scan's median (RefineConfig::pixel_stride); a scan with a
      // point cloud (a fragment) gives ICP that cloud instead of its depth pixels.
      if (const std::optional<double> a = MeasureDepthNoiseAt1m(scan)) {
        const bool coarser =
            config.refine.pixel_stride == 0 && scan.points.empty() && *a > kNoisyDepthAt1mM;
        std::printf("  depth noise of the scan (median of its views): %.2f mm at 1 m%s\n",
                    *a * 1000.0,
                    coarser ? " (noisier than 3 mm: ICP samples the coarser grid)" : "");
      }
    }
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
