// `zeroreg eval`: the paper's experiments as commands (docs/EVAL.md).
//
//   zeroreg eval 3dmatch --data ../shared/data/7scenes-redkitchen --gt ../shared/data/3dmatch-gt
//                        --out results/3dmatch [--method zeroreg|image|fpfh] [--views 3]
//   zeroreg eval pairs --data DIR --gap 20 [--step 10] [--first 0] --out results/pairs-g20
//   zeroreg eval pairs --data DIR --list ../shared/lists/hololens-gap1 --out results/hololens-gap1
//   zeroreg eval merge results/shard-0 results/shard-1 ... --out results/merged
#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "commands.hpp"
#include "config_options.hpp"
#include "eval/fragments.hpp"
#include "eval/methods.hpp"
#include "eval/pair_list.hpp"
#include "eval/prior.hpp"
#include "eval/protocols.hpp"
#include "eval/runner.hpp"
#include "eval/session.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// --jobs: 0 means one job per processor this process may run on (as `nproc` counts them: the
// affinity mask that taskset, cgroups' cpusets or a Slurm allocation set, else every hardware
// thread). Pairs are independent and a record depends on its inputs and seed only (fpfh: with
// OMP_NUM_THREADS=1, docs/EVAL.md), so using every core changes the time, never a record. Memory
// grows with the count: the jobs share one prepared-scan cache (its budget holds), but each adds
// its working memory, and `eval 3dmatch` fuses that many fragments at once (docs/EVAL.md). At most
// 256, the bound of --jobs.
int JobsToRun(int requested) {
  if (requested > 0) return requested;
  constexpr int kMaxJobs = 256;
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof(allowed), &allowed) == 0 && CPU_COUNT(&allowed) > 0) {
    return std::min(kMaxJobs, CPU_COUNT(&allowed));
  }
  return static_cast<int>(
      std::clamp(std::thread::hardware_concurrency(), 1u, static_cast<unsigned>(kMaxJobs)));
}

// Options every protocol shares.
struct CommonOptions {
  std::string out, method = "zeroreg", pairs_file, shard = "0/1";
  int jobs = 0, limit = 0;  // jobs 0 = one per processor this process may use (JobsToRun)
  bool no_progress = false;
  PreparedCacheOptions cache;  // zeroreg / image: prepared scans kept across pairs
  ConfigOptions config;
  // --prior-error-deg / --prior-error-m (either one turns the prior on) and its tolerance.
  PriorError prior;
  bool prior_error_given = false, prior_tolerance_given = false;
};

void AddCommonOptions(CLI::App& app, CommonOptions* o) {
  app.add_option("--out,-o", o->out,
                 "results folder (pairs.jsonl, summary.json/.md, run.json); an existing one is "
                 "resumed")
      ->required();
  app.add_option("--method,-m", o->method,
                 "zeroreg (the pipeline with --config/--set), image (its whole-image feature "
                 "path), fpfh (Open3D FPFH + RANSAC), sift or orb (OpenCV features, ratio test, "
                 "depth lifting, RANSAC)")
      ->capture_default_str();
  app.add_option(
         "--jobs,-j", o->jobs,
         "pairs evaluated in parallel (zeroreg/image: sharing one Pipeline and its prepared "
         "scans); 0 = one per processor this process may use (" +
             std::to_string(JobsToRun(0)) +
             " here, at most 256). zeroreg, image, sift and orb records are the same for any value")
      ->capture_default_str()
      ->check(InRange(0, 256, /*integer=*/true));
  app.add_option("--limit", o->limit, "only the first N selected pairs (0 = all)")
      ->check(AtLeast(0, /*integer=*/true));
  app.add_option("--pairs", o->pairs_file,
                 "only these pairs: a file of lines \"i j\" (target i, source j as in gt.log)");
  app.add_option("--shard", o->shard,
                 "evaluate shard i of N (0-based, \"i/N\"); merge the folders with "
                 "`zeroreg eval merge`")
      ->capture_default_str();
  app.add_flag("--no-progress", o->no_progress, "no progress bar on stderr");
  app.add_option("--prepared-cache", o->cache.max_scans,
                 "zeroreg/image: scans kept prepared (features, objects, clouds) for the later "
                 "pairs that name them, least recently used out first; 0 = prepare both scans "
                 "of every pair (results are identical either way)")
      ->capture_default_str()
      ->check(InRange(0, 100000, /*integer=*/true));
  app.add_option_function<double>(
         "--prepared-cache-mib",
         [o](double mib) { o->cache.max_bytes = static_cast<size_t>(mib * 1024 * 1024); },
         "zeroreg/image: at most this much memory held by the prepared scans [default 512]")
      ->check(InRange(1, 1 << 20, /*integer=*/false));
  // Each sets one number of the prior and notes that it was given.
  const auto prior_option = [&app](const char* name, double* value, bool* given,
                                   const std::string& help, const CLI::Validator& check) {
    app.add_option_function<double>(
           name,
           [value, given](double v) {
             *value = v;
             *given = true;
           },
           help)
        ->check(check);
  };
  prior_option("--prior-error-deg", &o->prior.rotation_deg, &o->prior_error_given,
               "zeroreg/image: register every pair with a motion prior (as odometry would give) "
               "turned this many degrees from the ground truth about a random axis, drawn per pair "
               "from --seed (docs/EVAL.md)",
               InRange(0.0, 180.0, /*integer=*/false));
  prior_option("--prior-error-m", &o->prior.translation_m, &o->prior_error_given,
               "zeroreg/image: ... and moved this many metres from it in a random direction",
               AtLeast(0, /*integer=*/false));
  prior_option("--prior-max-rotation-deg", &o->prior.max_rotation_deg, &o->prior_tolerance_given,
               "how far (deg) a valid pose may turn from the prior, as register's [default 15]",
               CLI::Validator(PositiveNumber, "a positive number"));
  prior_option("--prior-max-translation-m", &o->prior.max_translation_m, &o->prior_tolerance_given,
               "how far (m) a valid pose may move from the prior, as register's [default 0.3]",
               CLI::Validator(PositiveNumber, "a positive number"));
  AddConfigOptions(app, &o->config);
}

// The command line as typed (from /proc on Linux), with the program shown as `zeroreg`.
std::string CommandLine() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string command = "zeroreg";
  size_t start = all.find('\0');
  while (start != std::string::npos && start + 1 < all.size()) {
    const size_t end = all.find('\0', start + 1);
    std::string arg = all.substr(start + 1, end == std::string::npos ? end : end - start - 1);
    if (arg.find_first_of(" \t'\"") != std::string::npos) arg = "'" + arg + "'";
    command += " " + arg;
    start = end;
  }
  return command;
}

// The selection before --shard: --pairs, then --limit.
std::vector<PairTask> Select(std::vector<PairTask> tasks, const CommonOptions& o) {
  if (!o.pairs_file.empty()) {
    tasks = FilterPairs(tasks, ReadPairsFile(o.pairs_file), "--pairs " + o.pairs_file);
  }
  if (o.limit > 0 && static_cast<size_t>(o.limit) < tasks.size()) tasks.resize(o.limit);
  return tasks;
}

struct Method {
  PipelineConfig pipeline;
  FpfhConfig fpfh;
  FeatureBaselineConfig features;   // sift / orb
  std::optional<PriorError> prior;  // --prior-error-deg / -m
  json settings;                    // the method part of run.json's settings
};

Method ResolveMethod(const CommonOptions& o) {
  CheckMethodName(o.method);
  Method m;
  m.pipeline = MethodPipelineConfig(o.method, BuildConfig(o.config));
  m.fpfh.seed = m.pipeline.seed;
  m.features.detector = o.method;
  m.features.seed = m.pipeline.seed;
  if (o.method == "fpfh") {
    m.settings = json{{"fpfh", FpfhConfigToJson(m.fpfh)}};
  } else if (o.method == "sift" || o.method == "orb") {
    m.settings = json{{"features", FeatureBaselineConfigToJson(m.features)}};
  } else {
    m.settings = json{{"pipeline", ConfigToJson(m.pipeline)}};
  }
  if (o.prior_tolerance_given && !o.prior_error_given) {
    throw MakeInputError("--prior-max-rotation-deg / --prior-max-translation-m",
                         "a tolerance needs a prior; give --prior-error-deg and/or "
                         "--prior-error-m");
  }
  if (o.prior_error_given) {
    if (!TakesMotionPrior(o.method)) {
      throw MakeInputError("--prior-error-deg / --prior-error-m",
                           "the " + o.method +
                               " baseline takes no motion prior; expected --method zeroreg or "
                               "image");
    }
    if (o.prior.rotation_deg > o.prior.max_rotation_deg ||
        o.prior.translation_m > o.prior.max_translation_m) {
      // Allowed (what a bad odometry does is worth measuring), but say what it means.
      std::fprintf(stderr,
                   "warning: the prior's error (%g deg, %g m) exceeds its tolerance (%g deg, %g "
                   "m): the ground truth itself lies outside it, so no right pose can be valid\n",
                   o.prior.rotation_deg, o.prior.translation_m, o.prior.max_rotation_deg,
                   o.prior.max_translation_m);
    }
    m.prior = o.prior;
    // Every result depends on it: a folder is resumed or merged only under the same prior.
    m.settings["prior"] = PriorErrorToJson(o.prior);
  }
  return m;
}

// The jobs that will run over `pairs` pairs: --jobs (JobsToRun), at most one per pair.
int JobsForPairs(const CommonOptions& o, size_t pairs) {
  const size_t jobs = std::min(static_cast<size_t>(JobsToRun(o.jobs)), pairs);
  return static_cast<int>(std::max<size_t>(jobs, 1));
}

// Unless the config gives `threads`, the jobs share the processors: each job's pipeline gets
// processors / jobs threads, at least 1 and at most the config's, counting only the jobs that will
// run (at most one per pair). With as many jobs as processors a pipeline's second thread only
// competes with the other job's (4-5 % more wall time and 30-75 MiB more memory over 20 pairs,
// docs/SPEED.md). No result depends on it; run.json records the value used.
void ShareProcessors(const CommonOptions& o, size_t pairs, Method* m, RunInfo* info) {
  if (GivesTopLevelKey(o.config, "threads")) return;
  m->pipeline.threads =
      std::min(m->pipeline.threads, std::max(1, JobsToRun(0) / JobsForPairs(o, pairs)));
  if (m->settings.contains("pipeline")) {
    m->settings["pipeline"]["threads"] = m->pipeline.threads;
    info->settings["pipeline"]["threads"] = m->pipeline.threads;
  }
}

// The prepared-scan cache of this run's pairs: scans that are a target in none of them are
// prepared as sources only.
PreparedCacheOptions CacheFor(const CommonOptions& o, const std::vector<PairTask>& mine) {
  PreparedCacheOptions cache = o.cache;
  cache.target_refs = TargetRefs(mine);
  return cache;
}

// "zeroreg, 2 jobs x 1 thread": the progress bar says how the run uses the machine, since --jobs
// and the threads per job are chosen from the processors unless given.
std::string ProgressLabel(const std::string& method, int jobs, const json& settings) {
  const auto count = [](int n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
  };
  std::string label = method + ", " + count(jobs, "job");
  if (settings.contains("pipeline") && settings["pipeline"].contains("threads")) {
    label += " x " + count(settings["pipeline"]["threads"].get<int>(), "thread");
  }
  return label;
}

// Runs the selected pairs of this shard and writes the summary; shared by both protocols.
int RunAndSummarize(const CommonOptions& o, const Method& method, const RunInfo& info,
                    const std::vector<PairTask>& mine, const MethodFactory& factory,
                    const ScanLoader& loader) {
  RunOptions run;
  run.jobs = JobsToRun(o.jobs);
  run.prior = method.prior;
  run.seed = method.pipeline.seed;
  run.progress = !o.no_progress;
  run.label = ProgressLabel(o.method, JobsForPairs(o, mine.size()), info.settings);
  RunStats stats;
  const std::string jsonl = (fs::path(o.out) / "pairs.jsonl").string();
  const std::vector<PairRecord> records =
      RunPairs(mine, o.method, factory, loader, jsonl, run, &stats);
  const EvalSummary summary = WriteSummary(o.out, info, mine, records);
  std::printf("%s\n", summary.markdown.c_str());
  std::printf("%d pairs evaluated now, %d reused from %s; summary in %s/summary.md\n", stats.ran,
              stats.reused, jsonl.c_str(), o.out.c_str());
  if (stats.errors > 0) {
    std::fprintf(stderr,
                 "%d pairs failed with an error (see the messages above); they are not counted "
                 "as done, and rerunning the same command retries them\n",
                 stats.errors);
    return kExitRegistrationFailed;
  }
  return kExitOk;
}

struct MatchOptions {
  CommonOptions common;
  std::string data, gt, scene = "7-scenes-redkitchen", cache = "cache/fragments";
  std::string benchmarks = "3DMatch,3DLoMatch";
  int frames_per_fragment = 50;
  bool fuse_only = false;
  double depth_scale = 0.0;
  FuseConfig fuse;
};

// "3DMatch,3DLoMatch" -> the names, each checked.
std::vector<std::string> ParseBenchmarks(const std::string& text) {
  std::vector<std::string> names;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string name = text.substr(start, comma == std::string::npos ? comma : comma - start);
    if (name != "3DMatch" && name != "3DLoMatch") {
      throw MakeInputError("--benchmarks " + text,
                           "unknown benchmark '" + name + "'; expected 3DMatch and/or 3DLoMatch");
    }
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return names;
}

int RunMatch(const MatchOptions& o) {
  Method method = ResolveMethod(o.common);
  DatasetOptions dataset_options;
  dataset_options.depth_scale = o.depth_scale;
  const auto dataset = OpenDataset(o.data, dataset_options);
  const std::vector<int> available = AvailableFragments(dataset->FrameIds(), o.frames_per_fragment);
  if (available.empty()) {
    throw MakeInputError(o.data, "holds no complete fragment of " +
                                     std::to_string(o.frames_per_fragment) +
                                     " consecutive frames (fragment k = frames 50k..50k+49)");
  }
  FragmentSource fragments;
  fragments.dataset = dataset.get();
  fragments.frames_per_fragment = o.frames_per_fragment;
  fragments.fuse = o.fuse;
  fragments.cache_dir = o.cache;
  fragments.scene = o.scene;
  fragments.depth_scale = o.depth_scale;

  std::vector<PairTask> tasks;
  for (const std::string& b : ParseBenchmarks(o.benchmarks)) {
    for (PairTask t : ThreeDMatchTasks(o.gt, b, o.scene, available)) {
      t.target_ref = fragments.ScanJson(t.target_id);
      t.source_ref = fragments.ScanJson(t.source_id);
      tasks.push_back(t);
    }
  }
  if (tasks.empty()) {
    throw MakeInputError("--benchmarks " + o.benchmarks,
                         "selects no pair; expected 3DMatch, 3DLoMatch or both, with fragments "
                         "available in --data");
  }
  RunInfo info;
  info.protocol = "3dmatch";
  info.method = o.common.method;
  info.settings = method.settings;
  info.settings["data"] = o.data;
  info.settings["gt"] = o.gt;
  info.settings["scene"] = o.scene;
  info.settings["frames_per_fragment"] = o.frames_per_fragment;
  info.settings["fuse"] = {{"num_views", o.fuse.num_views},
                           {"voxel_length_m", o.fuse.voxel_length_m},
                           {"sdf_trunc_m", o.fuse.sdf_trunc_m},
                           {"max_depth_m", o.fuse.max_depth_m},
                           {"output_voxel_m", o.fuse.output_voxel_m}};
  // The fragments depend on it; recorded only when given, so folders of the default still resume.
  if (o.depth_scale != 0.0) info.settings["fuse"]["depth_scale"] = o.depth_scale;
  info.tasks = Select(tasks, o.common);
  info.shard = o.common.shard;
  info.command = CommandLine();
  const std::vector<PairTask> mine = ApplyShard(info.tasks, ParseShard(o.common.shard));
  ShareProcessors(o.common, mine.size(), &method, &info);

  // The method first: a bad config or missing model is reported before minutes of fusion.
  const MethodFactory factory =
      o.fuse_only ? MethodFactory()
                  : MakeMethodFactory(o.common.method, method.pipeline, method.fpfh,
                                      method.features, CacheFor(o.common, mine));
  const OutDirLock lock = PrepareOutDir(o.common.out, info);

  // Lazy fusion: only the fragments of this shard's pairs that are not finished yet.
  const std::vector<std::string> done_keys =
      DoneKeys((fs::path(o.common.out) / "pairs.jsonl").string());
  const std::set<std::string> done(done_keys.begin(), done_keys.end());
  std::set<int> needed;
  for (const PairTask& t : mine) {
    if (done.count(t.Key())) continue;
    needed.insert(t.target_id);
    needed.insert(t.source_id);
  }
  const int built = EnsureFragments(fragments, std::vector<int>(needed.begin(), needed.end()),
                                    JobsToRun(o.common.jobs), !o.common.no_progress);
  std::fprintf(stderr, "fragments: %zu needed, %d fused now, %zu reused from %s\n", needed.size(),
               built, needed.size() - built, o.cache.c_str());
  if (o.fuse_only) return kExitOk;
  return RunAndSummarize(o.common, method, info, mine, factory, ScanLoader(dataset_options));
}

struct FramePairOptions {
  CommonOptions common;
  std::string data, list;
  int gap = 20, step = 10, first = 0;
  double depth_scale = 0.0;
};

int RunFramePairs(const FramePairOptions& o) {
  Method method = ResolveMethod(o.common);
  DatasetOptions dataset_options;
  dataset_options.depth_scale = o.depth_scale;
  const auto dataset = OpenDataset(o.data, dataset_options);
  fs::path root = fs::path(o.data).lexically_normal();
  if (root.filename().empty()) root = root.parent_path();
  std::vector<PairTask> tasks;
  json list_settings;
  if (!o.list.empty()) {
    const PairList list =
        ReadPairList(o.list, dataset->FrameIds(), o.data, root.filename().string());
    tasks = list.tasks;
    list_settings = list.settings;
  } else {
    tasks = FramePairTasks(dataset->FrameIds(), o.gap, o.step, o.first, o.data,
                           root.filename().string());
    if (tasks.empty()) {
      throw MakeInputError(o.data, "has no frame pair (i, i + " + std::to_string(o.gap) +
                                       ") from frame " + std::to_string(o.first));
    }
  }
  RunInfo info;
  info.protocol = "pairs";
  info.method = o.common.method;
  info.settings = method.settings;
  info.settings["data"] = o.data;
  info.settings["depth_scale"] = o.depth_scale;
  // A list run keeps the list's identity (name and content hashes): a resumed folder refuses
  // another list, and the summary writes <out>/est.log.
  if (!list_settings.is_null()) info.settings["list"] = list_settings;
  info.tasks = Select(tasks, o.common);
  info.shard = o.common.shard;
  info.command = CommandLine();
  const std::vector<PairTask> mine = ApplyShard(info.tasks, ParseShard(o.common.shard));
  ShareProcessors(o.common, mine.size(), &method, &info);
  const MethodFactory factory = MakeMethodFactory(o.common.method, method.pipeline, method.fpfh,
                                                  method.features, CacheFor(o.common, mine));
  const OutDirLock lock = PrepareOutDir(o.common.out, info);
  return RunAndSummarize(o.common, method, info, mine, factory, ScanLoader(dataset_options));
}

struct MergeOptions {
  std::vector<std::string> dirs;
  std::string out;
};

int RunMerge(const MergeOptions& o) {
  for (const std::string& d : o.dirs) {
    if (fs::exists(d) && fs::exists(o.out) && fs::equivalent(d, o.out)) {
      throw MakeInputError("--out " + o.out, "is one of the folders to merge; expected a new one");
    }
  }
  int missing = 0;
  const EvalSummary summary = MergeRuns(o.dirs, o.out, &missing);
  std::printf("%s\n", summary.markdown.c_str());
  std::printf("merged %zu folders into %s\n", o.dirs.size(), o.out.c_str());
  if (missing > 0) {
    std::fprintf(stderr,
                 "warning: %d selected pairs are in none of the folders (unfinished shards?); "
                 "the recall counts them as failures\n",
                 missing);
  }
  return kExitOk;
}

}  // namespace

Runner AddEvalCommand(CLI::App& app) {
  app.require_subcommand(1);

  auto m = std::make_shared<MatchOptions>();
  CLI::App* match = app.add_subcommand(
      "3dmatch",
      "3DMatch / 3DLoMatch pairs of fragments rebuilt from RGB-D (paper Tables 1, 4, 5)");
  match->add_option("--data,-d", m->data, "RGB-D frames of the scene (3DMatch layout)")->required();
  match->add_option("--gt", m->gt, "benchmark ground truth: <gt>/{3DMatch,3DLoMatch}/<scene>/")
      ->required();
  match->add_option("--scene", m->scene, "scene name in --gt")->capture_default_str();
  match->add_option("--benchmarks", m->benchmarks, "3DMatch, 3DLoMatch or both (comma-separated)")
      ->capture_default_str();
  match->add_option("--cache", m->cache, "fragment cache folder (git-ignored)")
      ->capture_default_str();
  match->add_option("--views", m->fuse.num_views, "views kept per fragment (paper Table 5)")
      ->capture_default_str()
      ->check(InRange(1, 50, /*integer=*/true));
  match
      ->add_option("--fuse-voxel", m->fuse.voxel_length_m,
                   "TSDF voxel of the fragment fusion in metres (coarser = faster, e.g. for CI)")
      ->capture_default_str()
      ->check(InRange(FuseConfig::kMinVoxelLengthM, FuseConfig::kMaxVoxelLengthM, false));
  match->add_option("--frames-per-fragment", m->frames_per_fragment, "frames fused per fragment")
      ->capture_default_str()
      ->check(AtLeast(1, /*integer=*/true));
  match->add_option("--depth-scale", m->depth_scale,
                    "raw depth units per metre (default: layout's)");
  match->add_flag("--fuse-only", m->fuse_only,
                  "only fuse the fragments the selected pairs need, then stop");
  AddCommonOptions(*match, &m->common);

  auto f = std::make_shared<FramePairOptions>();
  CLI::App* pairs = app.add_subcommand(
      "pairs", "frame pairs (i, i + gap) of an RGB-D sequence (UR&R protocol, paper Table 3)");
  pairs->add_option("--data,-d", f->data, "RGB-D sequence (3DMatch, TUM or ScanNet layout)")
      ->required();
  CLI::Option* gap = pairs->add_option("--gap,-g", f->gap, "frame gap g")
                         ->capture_default_str()
                         ->check(AtLeast(1, /*integer=*/true));
  CLI::Option* step = pairs->add_option("--step", f->step, "every step-th i")
                          ->capture_default_str()
                          ->check(AtLeast(1, /*integer=*/true));
  CLI::Option* first = pairs->add_option("--first", f->first, "first i")
                           ->capture_default_str()
                           ->check(AtLeast(0, /*integer=*/true));
  pairs
      ->add_option("--list", f->list,
                   "pair list folder instead of --gap: pairs.txt (\"i j\" = target i, source j) "
                   "and gt.log (T_i_j); writes <out>/est.log")
      ->excludes(gap)
      ->excludes(step)
      ->excludes(first);
  pairs->add_option("--depth-scale", f->depth_scale,
                    "raw depth units per metre (default: layout's)");
  AddCommonOptions(*pairs, &f->common);

  auto g = std::make_shared<MergeOptions>();
  CLI::App* merge = app.add_subcommand(
      "merge", "merge the results folders of --shard runs and recompute the summary");
  merge->add_option("dirs", g->dirs, "results folders of the shards")->required()->expected(1, -1);
  merge->add_option("--out,-o", g->out, "merged results folder")->required();

  auto sessions_run = std::make_shared<Runner>();
  CLI::App* sessions = AddEvalSessionsCommand(app, sessions_run.get());

  return [=]() {
    if (sessions->parsed()) return (*sessions_run)();
    if (match->parsed()) return RunMatch(*m);
    if (pairs->parsed()) return RunFramePairs(*f);
    return RunMerge(*g);
  };
}

}  // namespace zeroreg::cli
