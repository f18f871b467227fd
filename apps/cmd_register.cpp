#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "config_options.hpp"
#include "eval/methods.hpp"
#include "eval/metrics.hpp"
#include "io/text_parsing.hpp"
#include "parallel/run_both.hpp"
#include "viz/pictures.hpp"
#include "viz/ply.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg::cli {
namespace {

struct RegisterOptions {
  std::string source, target, out, gt, viz, out_dir, prior;
  MotionPrior prior_tolerance;  // its T_target_source is read from `prior`
  double depth_scale = 0.0;
  bool with_correspondences = false;
  bool timings = false;
  std::string baseline;  // "", "sift" or "orb"
  ConfigOptions config;
};

void PrintTransform(const Transform& T) {
  for (int r = 0; r < 4; ++r) {
    std::printf("  [% .6f % .6f % .6f % .6f]\n", T(r, 0), T(r, 1), T(r, 2), T(r, 3));
  }
}

// Refuses an output that is one of the run's inputs (--out naming the source image, --out-dir
// holding the --gt file as result.json, ...): the result would replace what it was computed from.
// Paths are compared as files (links and hard links included), before anything is read or written.
void RefuseOutputsThatAreInputs(const RegisterOptions& o, const DatasetOptions& dataset_options) {
  namespace fs = std::filesystem;
  using Named = std::vector<std::pair<std::string, std::string>>;  // (option, path)
  Named inputs;
  for (const auto& [option, spec] : Named{{"--source", o.source}, {"--target", o.target}}) {
    try {
      for (const std::string& file : ScanInputFiles(spec, dataset_options)) {
        inputs.emplace_back(option, file);
      }
    } catch (const std::exception&) {
      // Reading the scan names the problem.
    }
  }
  for (const auto& [option, file] :
       Named{{"--gt", o.gt}, {"--prior", o.prior}, {"--config", o.config.config_file}}) {
    if (!file.empty()) inputs.emplace_back(option, file);
  }
  Named outputs;
  if (!o.out.empty()) outputs.emplace_back("--out", o.out);
  if (!o.out_dir.empty()) {
    for (const char* name : {"result.json", "registered.ply", "source.ply", "target.ply"}) {
      outputs.emplace_back("--out-dir", (fs::path(o.out_dir) / name).string());
    }
  }
  // The picture folders lose their earlier pictures: an input among them would go too.
  Named picture_folders;
  if (!o.viz.empty()) picture_folders.emplace_back("--viz", o.viz);
  if (!o.out_dir.empty()) {
    picture_folders.emplace_back("--out-dir", (fs::path(o.out_dir) / "pictures").string());
  }
  for (const auto& [input_option, input] : inputs) {
    std::error_code ec;
    for (const auto& [option, output] : outputs) {
      if (fs::equivalent(output, input, ec) && !ec) {
        throw MakeInputError(option + " " + output, "is the " + input_option + " file " + input +
                                                        ", which the result would overwrite; "
                                                        "expected another file name");
      }
    }
    for (const auto& [option, folder] : picture_folders) {
      const fs::path parent =
          fs::path(input).parent_path().empty() ? fs::path(".") : fs::path(input).parent_path();
      if (IsRegistrationPictureName(fs::path(input).filename().string()) &&
          fs::equivalent(parent, folder, ec) && !ec) {
        throw MakeInputError(option + " " + folder, "its pictures would replace the " +
                                                        input_option + " file " + input +
                                                        "; expected another folder");
      }
    }
  }
}

}  // namespace

Runner AddRegisterCommand(CLI::App& app) {
  auto o = std::make_shared<RegisterOptions>();
  app.add_option("--source,-s", o->source,
                 "source scan: DIR@FRAME, a frame's colour image, scan.json or its folder")
      ->required();
  app.add_option("--target,-t", o->target, "target scan (same forms as --source)")->required();
  app.add_option("--out,-o", o->out, "write the result as JSON to this file");
  app.add_option("--gt", o->gt,
                 "ground-truth T_target_source as a 4x4 text file (default: from the scans' "
                 "poses when both have them)");
  CLI::Option* prior_option = app.add_option(
      "--prior", o->prior,
      "motion prior T_target_source as a 4x4 text file (odometry, IMU): only a pose "
      "within --prior-max-rotation-deg and --prior-max-translation-m of it can be valid, "
      "and ICP from it is tried when no source gives one (symmetric scenes)");
  // A tolerance without a prior would be silently ignored: CLI11 refuses it by name instead.
  app.add_option("--prior-max-rotation-deg", o->prior_tolerance.max_rotation_deg,
                 "how far (deg) a valid pose may turn from --prior")
      ->capture_default_str()
      ->check(PositiveNumber)
      ->needs(prior_option);
  app.add_option("--prior-max-translation-m", o->prior_tolerance.max_translation_m,
                 "how far (m) a valid pose may move from --prior")
      ->capture_default_str()
      ->check(PositiveNumber)
      ->needs(prior_option);
  app.add_option("--depth-scale", o->depth_scale,
                 "raw depth units per metre (default: the layout's, 1000 or TUM's 5000)");
  app.add_option("--viz", o->viz,
                 "write pictures (objects, correspondences, registered clouds) per view pair "
                 "into this folder");
  app.add_option("--out-dir", o->out_dir,
                 "write DIR/result.json (as --out), DIR/pictures/ (as --viz) and the clouds as "
                 "coloured PLY: DIR/registered.ply (target blue, source moved into the target "
                 "frame orange), DIR/source.ply and DIR/target.ply (own frames and colours); "
                 "`zeroreg report DIR` makes a page of it");
  app.add_flag("--with-correspondences", o->with_correspondences,
               "include every 3D correspondence in the JSON result");
  app.add_option("--baseline", o->baseline,
                 "register with the classical baseline instead of the pipeline: sift or orb "
                 "(OpenCV keypoints, ratio test, depth lifting, RANSAC; the --method of `zeroreg "
                 "eval`), for comparing whole-process time (scripts/bench-speed.sh)")
      ->check(CLI::IsMember({"sift", "orb"}))
      ->excludes(prior_option);  // the baselines take no prior
  app.add_flag("--timings", o->timings,
               "print the wall time of every stage on stderr, one per line, from reading the "
               "scans and loading the models to the pictures and files written");
  AddConfigOptions(app, &o->config);

  return [o]() {
    // Output paths first: a registration can take seconds, and its result must not be lost.
    if (!o->out.empty()) CheckOutputFile(o->out, "--out");
    if (!o->out_dir.empty() && std::filesystem::exists(o->out_dir) &&
        !std::filesystem::is_directory(o->out_dir)) {
      throw MakeInputError("--out-dir " + o->out_dir, "is a file; expected a folder");
    }
    const PipelineConfig config = BuildConfig(o->config);
    DatasetOptions dataset_options;
    dataset_options.depth_scale = o->depth_scale;
    RefuseOutputsThatAreInputs(*o, dataset_options);
    const auto process_start = std::chrono::steady_clock::now();
    auto last = process_start;
    // Wall time since the previous call, ms.
    const auto lap = [&last]() {
      const auto now = std::chrono::steady_clock::now();
      const double ms = std::chrono::duration<double, std::milli>(now - last).count();
      last = now;
      return ms;
    };
    // With threads >= 2 the models load while the scans are read, and the two scans are read at
    // once (a fragment is a cloud and six PNGs: ~190 ms one after the other). Errors are reported
    // in the serial order whatever the thread count: the source's, the target's, --prior's,
    // --gt's, the models'.
    const bool overlap = config.threads >= 2;
    const auto ms_since = [](std::chrono::steady_clock::time_point start) {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
    };
    Scan source, target;
    std::optional<Transform> T_gt;
    std::optional<MotionPrior> prior;
    double read_ms = 0, models_ms = 0;
    std::optional<Pipeline> pipeline;
    const auto read_inputs = [&] {
      const auto start = std::chrono::steady_clock::now();
      RunBoth(
          overlap, [&] { source = LoadScan(o->source, dataset_options); },
          [&] { target = LoadScan(o->target, dataset_options); });
      read_ms = ms_since(start);
      if (!o->prior.empty()) {
        prior = o->prior_tolerance;
        prior->T_target_source = ReadPoseFile(o->prior);
      }
      if (!o->gt.empty()) {
        T_gt = ReadPoseFile(o->gt);
      } else if (source.T_world_scan_gt && target.T_world_scan_gt) {
        T_gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
      }
    };
    const auto load_models = [&] {
      const auto start = std::chrono::steady_clock::now();
      pipeline.emplace(config);
      models_ms = ms_since(start);
    };
    if (o->baseline.empty()) {
      RunBoth(overlap, read_inputs, load_models);
    } else {
      read_inputs();
    }
    lap();
    if (!o->baseline.empty()) {
      FeatureBaselineConfig baseline;
      baseline.detector = o->baseline;
      baseline.seed = config.seed;
      const MethodOutput r = RunFeatureBaseline(baseline, source, target);
      const double register_ms = lap();
      std::printf("zeroreg register --baseline %s: %s -> %s\n", o->baseline.c_str(),
                  o->source.c_str(), o->target.c_str());
      PrintTransform(r.T_target_source);
      std::printf("verdict: %s (%s)\n", r.valid ? "VALID" : "FAILED", r.reason.c_str());
      if (T_gt) {
        std::printf("error vs ground truth: rotation %.3f deg, translation %.2f cm\n",
                    RotationErrorDeg(r.T_target_source, *T_gt),
                    TranslationErrorM(r.T_target_source, *T_gt) * 100);
      }
      if (o->timings) {
        std::fprintf(stderr, "timings (ms):\n  %-14s %9.1f\n  %-14s %9.1f\n", "read_scans", read_ms,
                     "register", register_ms);
      }
      if (!o->out.empty()) {
        const nlohmann::json out{
            {"source", o->source},
            {"target", o->target},
            {"baseline", FeatureBaselineConfigToJson(baseline)},
            {"result",
             {{"T_target_source", TransformToJson(r.T_target_source)},
              {"valid", r.valid},
              {"reason", r.reason},
              {"timings_ms", {{"read_scans", read_ms}, {"register", register_ms}}}}}};
        detail::WriteFileAtomically(o->out, detail::DumpJson(out, 2) + "\n");
      }
      return r.valid ? kExitOk : kExitRegistrationFailed;
    }

    RegistrationResult result = pipeline->Register(source, target, prior);
    lap();
    // The process's own stages go first in timings_ms; "total" stays the registration's.
    result.timings.insert(result.timings.begin(),
                          {{"read_scans", read_ms}, {"load_models", models_ms}});

    std::printf("zeroreg register: %s -> %s\n", o->source.c_str(), o->target.c_str());
    std::printf("T_target_source (%s path):\n", PathName(result.path).c_str());
    PrintTransform(result.T_target_source);
    std::printf("verdict: %s (%s)\n", result.valid ? "VALID" : "FAILED", result.reason.c_str());
    std::printf("keypoints %d / %d, correspondences %d, inliers %d (ratio %.3f, rmse %.1f mm)\n",
                result.num_keypoints_source, result.num_keypoints_target,
                result.num_correspondences, result.num_inliers, result.inlier_ratio,
                result.inlier_rmse * 1000);
    // Timings go to stderr so that stdout is the same for the same input and seed.
    std::fprintf(stderr, "time:");
    for (const StageTime& t : result.timings) {
      std::fprintf(stderr, " %s %.0f ms", t.stage.c_str(), t.ms);
    }
    std::fprintf(stderr, "\n");

    nlohmann::json out{{"source", o->source},
                       {"target", o->target},
                       {"result", ResultToJson(result, o->with_correspondences)},
                       {"config", ConfigToJson(config)},
                       {"seed", config.seed}};
    if (prior) {
      out["prior"] = {{"T_target_source", TransformToJson(prior->T_target_source)},
                      {"max_rotation_deg", prior->max_rotation_deg},
                      {"max_translation_m", prior->max_translation_m}};
    }
    if (T_gt) {
      const double rot = RotationErrorDeg(result.T_target_source, *T_gt);
      const double trans = TranslationErrorM(result.T_target_source, *T_gt);
      const double gt_inliers = CorrespondenceInlierRatio(result.correspondences, *T_gt);
      std::printf(
          "error vs ground truth: rotation %.3f deg, translation %.2f cm "
          "(correspondence inlier ratio %.3f at 0.1 m)\n",
          rot, trans * 100, gt_inliers);
      out["ground_truth"] = {{"T_target_source", TransformToJson(*T_gt)},
                             {"rotation_error_deg", rot},
                             {"translation_error_cm", trans * 100},
                             {"correspondence_inlier_ratio", gt_inliers}};
    }
    if (!o->viz.empty()) {
      const auto pictures =
          WriteRegistrationPictures(o->viz, source, target, result, config.verify, config.depth);
      std::printf("%zu pictures written to %s\n", pictures.size(), o->viz.c_str());
    }
    // Paths that are not UTF-8 are written with U+FFFD in the JSON; the file is replaced
    // atomically, so it is never left empty.
    const std::string result_text = detail::DumpJson(out, 2) + "\n";
    if (!o->out.empty()) {
      detail::WriteFileAtomically(o->out, result_text);
      std::printf("result written to %s\n", o->out.c_str());
    }
    if (!o->out_dir.empty()) {
      const std::filesystem::path dir(o->out_dir);
      std::error_code ec;
      std::filesystem::create_directories(dir, ec);
      if (ec) throw MakeInputError(o->out_dir, "cannot create the folder (" + ec.message() + ")");
      detail::WriteFileAtomically((dir / "result.json").string(), result_text);
      const auto pictures = WriteRegistrationPictures((dir / "pictures").string(), source, target,
                                                      result, config.verify, config.depth);
      const RegisteredPlyFiles ply =
          WriteRegisteredPly(o->out_dir, source, target, result.T_target_source);
      std::printf(
          "result, %zu pictures and registered.ply (%zu target + %zu source points) "
          "written to %s\n",
          pictures.size(), ply.num_target, ply.num_source, o->out_dir.c_str());
    }
    if (o->timings) {
      const double output_ms = lap();
      std::fprintf(stderr, "timings (ms; with threads >= 2 the two scans' stages overlap):\n");
      for (const StageTime& t : result.timings) {
        std::fprintf(stderr, "  %-14s %9.1f\n", t.stage.c_str(), t.ms);
      }
      std::fprintf(stderr, "  %-14s %9.1f\n", "write_output", output_ms);
      std::fprintf(stderr, "  %-14s %9.1f\n", "process",
                   std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                             process_start)
                       .count());
    }
    return result.valid ? kExitOk : kExitRegistrationFailed;
  };
}

}  // namespace zeroreg::cli
