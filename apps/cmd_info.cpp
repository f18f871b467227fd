#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <opencv2/core/version.hpp>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "config_options.hpp"
#include "estimate/depth_noise.hpp"
#include "estimate/working_scale.hpp"
#include "inference/onnx_model.hpp"
#include "io/text_parsing.hpp"
#include "open3d_module/open3d_module.hpp"
#include "segment/segmenter.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg::cli {
namespace {

struct InfoOptions {
  std::string scan;
  ConfigOptions config;
};

// Which engine runs the models, and why: the line a bug report about inference needs first. False
// when the config names no engine this build has (bad input, printed rather than thrown so that
// the rest of the report still prints).
bool PrintInferenceEngine(const InferenceConfig& inference) {
  const std::string opencv = std::string("OpenCV ") + CV_VERSION + " DNN";
  const std::string ort_version = OnnxRuntimeVersion();
  const std::string ort_library = OnnxRuntimeLibraryPath();
  const std::string ort =
      OnnxRuntimeAvailable()
          ? "ONNX Runtime " + ort_version + ", " +
                (ort_library.empty() ? "library path unknown" : ort_library)
          : std::string("not in this build (CMake ZEROREG_WITH_ONNXRUNTIME; docs/INSTALL.md)");
  bool resolved = true;
  try {
    const InferenceEngine engine = ResolveEngine(inference);
    std::string why;
    if (inference.engine == "auto") {
      why = OnnxRuntimeAvailable() ? "inference.engine = auto, and this build links ONNX Runtime"
                                   : "inference.engine = auto, and this build has no ONNX Runtime";
    } else {
      why = "inference.engine = " + inference.engine;
    }
    std::printf("inference engine: %s (%s)\n", EngineName(engine).c_str(), why.c_str());
  } catch (const InputError& e) {
    std::printf("inference engine: NONE: %s\n", e.what());
    resolved = false;
  }
  std::printf("  onnxruntime: %s\n", ort.c_str());
  std::printf("  opencv: %s (in every build: the fallback engine)\n", opencv.c_str());
  return resolved;
}

// Every file of the assets folder's sha256 list, checked as a registration checks the models it
// loads; a problem is printed with the fix RequireAsset names, not thrown.
void PrintAssets(const std::string& assets_dir) {
  std::string assets;
  try {
    assets = ResolveAssetsDir(assets_dir);
  } catch (const InputError& e) {
    std::printf("assets: NOT FOUND: %s\n", e.what());
    return;
  }
  std::printf("assets: %s\n", assets.c_str());
  std::ifstream list(assets + "/assets.sha256");
  if (!list) {
    std::printf("  no assets.sha256 in it (bash scripts/fetch-assets.sh writes one)\n");
    return;
  }
  int files = 0, bad = 0;
  std::string line;
  while (std::getline(list, line)) {
    std::istringstream fields(line);
    std::string digest, file;
    if (line.empty() || line[0] == '#' || !(fields >> digest >> file)) continue;
    ++files;
    try {
      RequireAsset(assets, file);
    } catch (const InputError& e) {
      ++bad;
      std::printf("  NOT OK %s\n", e.what());
    }
  }
  if (bad == 0) {
    std::printf("  %d model files, sha256 ok\n", files);
  } else {
    std::printf("  %d of %d model files do not verify (bash scripts/fetch-assets.sh)\n", bad,
                files);
  }
}

}  // namespace

Runner AddInfoCommand(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  app.add_option("--scan", o->scan, "also describe this scan (same forms as register --source)");
  AddConfigOptions(app, &o->config);
  return [o]() {
    const PipelineConfig config = BuildConfig(o->config);
    // What a bug report needs, in the order a reader checks it; the effective config last.
    std::printf("zeroreg %s\n", ZEROREG_VERSION);
    const bool engine_resolved = PrintInferenceEngine(config.inference);
    // Loaded here only to say where it is; a registration loads it only when it needs it.
    try {
      std::printf("open3d module: %s (loads; needed for FPFH, point cloud files, fusion)\n",
                  open3d_module::LoadedModulePath().c_str());
    } catch (const InputError& e) {
      std::printf("open3d module: NOT LOADABLE: %s\n", e.what());
    }
    PrintAssets(config.assets_dir);
    // What the launcher (apps/launcher/) or zeroreg-core's own re-execution set up.
    const char* tuning = std::getenv("ZEROREG_MALLOC_TUNING");
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    std::printf("malloc tuning: %s (GLIBC_TUNABLES=%s)\n", tuning ? tuning : "not applied",
                tunables ? tunables : "");
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
      const ScaleEvidence evidence = MeasureScale(scan);
      const std::optional<double> distance = evidence.distance_m;
      const double k = WorkingScale(evidence, config.scale);
      if (const std::optional<double> a = MeasureDepthNoiseAt1m(scan)) {
        // ICP decides in working units, where a reads k times larger.
        const bool coarser =
            config.refine.pixel_stride == 0 && scan.points.empty() && *a * k > kNoisyDepthAt1mM;
        std::printf(
            "  depth noise of the scan (median of its views): %.2f mm at 1 m%s\n", *a * 1000.0,
            !coarser   ? ""
            : k == 1.0 ? " (noisier than 3 mm: ICP samples the coarser grid)"
                       : " (noisier than 3 mm at the working scale: ICP samples the coarser grid)");
      }
      // The scale every length of the config is read at (docs/CONFIG.md, "Any scale").
      if (const std::optional<double> d = distance) {
        std::printf("  working distance %.3g m (median valid depth)", *d);
        if (const std::optional<double> a = MeasureDepthNoiseAt1m(scan)) {
          std::printf(", depth noise %.2g mm there, pixel footprint %.2g mm", *a * *d * *d * 1e3,
                      *d / scan.views.front().intrinsics.fx * 1e3);
        }
        const char* from =
            ScaleFromNoise(evidence, config.scale) ? " (read from the structured-light noise)" : "";
        if (k == 1.0) {
          std::printf("; working scale 1%s: the config's lengths apply as written\n", from);
        } else {
          std::printf(
              "; working scale %.3g%s: every length of the config is multiplied by it "
              "(RANSAC inlier distance %.3g m, ICP final gate %.3g m)\n",
              k, from, k * config.ransac.inlier_threshold_m,
              k * config.refine.max_distance_final_m);
        }
      }
    }
    std::printf("effective config:\n%s\n", detail::DumpJson(ConfigToJson(config), 2).c_str());
    return engine_resolved ? kExitOk : kExitBadInput;
  };
}

}  // namespace zeroreg::cli
