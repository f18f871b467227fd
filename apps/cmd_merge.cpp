// `zeroreg merge A B --out DIR` and `zeroreg loops SEQ --odometry traj.tum --out DIR`
// (docs/RECORDINGS.md "Merge and loops").
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "config_options.hpp"
#include "recording_options.hpp"
#include "recordings/edge_files.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg::cli {

void AddRecordingsOptions(CLI::App& app, RecordingsOptions* o) {
  app.add_option("--out,-o", o->out,
                 "output folder (T_A_B.txt, trajectories, loops.jsonl, loops.log, merged.ply, "
                 "report.html); an existing one made with the same settings is resumed")
      ->required();
  app.add_option("--keyframe-covisibility", o->config.keyframe_covisibility,
                 "a frame whose co-visibility with the last keyframe is below this is a keyframe")
      ->capture_default_str()
      ->check(InRange(0.01, 1.0, false));
  app.add_option("--keyframe-every", o->config.keyframe_every,
                 "without poses: every N-th frame is a keyframe")
      ->capture_default_str()
      ->check(AtLeast(1, true));
  app.add_option("--candidates", o->config.candidates_per_keyframe,
                 "candidate pairs per keyframe, best place-recognition scores first")
      ->capture_default_str()
      ->check(AtLeast(1, true));
  app.add_option("--min-loops", o->config.min_consistent_loops,
                 "mutually consistent loop closures needed to accept any")
      ->capture_default_str()
      ->check(AtLeast(1, true));
  app.add_option("--words", o->config.vocabulary_words, "place-recognition vocabulary size")
      ->capture_default_str()
      ->check(AtLeast(1, true));
  app.add_option("--cache-mib", o->cache_mib,
                 "prepared keyframes kept in memory (MiB); past it they are prepared again")
      ->capture_default_str()
      ->check(AtLeast(16, true));
  app.add_flag("--no-cloud", o->no_cloud, "do not write merged.ply");
  app.add_flag("--quiet,-q", o->quiet, "no progress lines on stderr");
  AddConfigOptions(app, &o->pipeline);
}

void AddShardOptions(CLI::App& app, RecordingsOptions* o) {
  app.add_option("--shard", o->shard,
                 "verify only shard I of N of the candidate pairs (I/N, 1 <= I <= N) into "
                 "OUT/edges-I-of-N.jsonl and stop; the last step reads every shard's file with "
                 "--edges (docs/RECORDINGS.md, \"Sharded verification\")");
  app.add_option("--edges", o->edges,
                 "the edge files of every shard (OUT/edges-*-of-N.jsonl of the --shard runs, "
                 "same recordings and options): read instead of verifying, then the loop "
                 "closures are decided and optimised and every output written");
}

RecordingInput RecordingFromOptions(const std::string& spec, const std::string& poses,
                                    const std::string& option) {
  RecordingInput r = ParseRecordingSpec(spec);
  if (poses == "none") return r;
  if (poses == "gt" || poses == "auto") {
    r.T_frame_camera = GroundTruthPoses(r);
    if (poses == "gt" && r.T_frame_camera.empty()) {
      throw InputError(option + " gt: " + r.root + " has no poses; give a trajectory file or none");
    }
    return r;
  }
  r.T_frame_camera = ReadTumTrajectory(poses);
  return r;
}

RecordingsConfig ConfigFromOptions(const RecordingsOptions& o) {
  RecordingsConfig config = o.config;
  config.pipeline = BuildConfig(o.pipeline);
  config.out_dir = o.out;
  config.progress = !o.quiet;
  config.write_cloud = !o.no_cloud;
  config.prepared_budget_bytes = static_cast<std::size_t>(o.cache_mib) << 20;
  if (!o.shard.empty()) {
    ParseShardSpec(o.shard, "--shard", &config.shard_index, &config.shard_count);
  }
  config.edge_files = o.edges;
  return config;
}

namespace {

void PrintStages(const RecordingsResult& r) {
  for (const StageReport& s : r.stages) {
    std::fprintf(stderr, "  %-18s %7.1f s  peak RSS %6.0f MiB\n", s.stage.c_str(), s.seconds,
                 s.peak_rss_mib);
  }
}

}  // namespace

Runner AddMergeCommand(CLI::App& app) {
  auto o = std::make_shared<RecordingsOptions>();
  auto a = std::make_shared<std::string>(), b = std::make_shared<std::string>();
  auto poses_a = std::make_shared<std::string>("auto"),
       poses_b = std::make_shared<std::string>("auto");
  app.add_option("A", *a, "recording A: a dataset folder, or DIR@FIRST-LAST (frame ids)")
      ->required();
  app.add_option("B", *b, "recording B, placed in A's frame")->required();
  app.add_option("--poses-a", *poses_a,
                 "A's poses: auto (the dataset's own when it has them), gt, none, or a TUM "
                 "trajectory file (first column the frame id)")
      ->capture_default_str();
  app.add_option("--poses-b", *poses_b, "B's poses, as --poses-a")->capture_default_str();
  AddRecordingsOptions(app, o.get());
  AddShardOptions(app, o.get());
  return [=]() {
    const RecordingInput ra = RecordingFromOptions(*a, *poses_a, "--poses-a");
    const RecordingInput rb = RecordingFromOptions(*b, *poses_b, "--poses-b");
    const RecordingsConfig config = ConfigFromOptions(*o);
    const RecordingsResult r = MergeRecordings(ra, rb, config);
    PrintStages(r);
    if (config.shard_count > 0) return kExitOk;  // the reason says what the shard wrote
    if (!r.found) {
      std::cerr << "zeroreg merge: " << r.reason << "\n";
      return kExitRegistrationFailed;
    }
    std::printf("T_A_B (maps B's frame into A's; %s/T_A_B.txt):\n", o->out.c_str());
    for (int row = 0; row < 4; ++row) {
      std::printf("%12.6f %12.6f %12.6f %12.6f\n", r.T_A_B(row, 0), r.T_A_B(row, 1),
                  r.T_A_B(row, 2), r.T_A_B(row, 3));
    }
    return kExitOk;
  };
}

Runner AddLoopsCommand(CLI::App& app) {
  auto o = std::make_shared<RecordingsOptions>();
  auto seq = std::make_shared<std::string>();
  auto odometry = std::make_shared<std::string>("auto");
  app.add_option("SEQ", *seq, "the sequence: a dataset folder, or DIR@FIRST-LAST (frame ids)")
      ->required();
  app.add_option("--odometry", *odometry,
                 "its poses: a TUM trajectory file (first column the frame id), auto (the "
                 "dataset's own when it has them), gt, or none")
      ->capture_default_str();
  app.add_option("--min-separation", o->config.min_separation,
                 "candidate pairs are keyframes at least this many keyframes apart")
      ->capture_default_str()
      ->check(AtLeast(1, true));
  AddRecordingsOptions(app, o.get());
  AddShardOptions(app, o.get());
  return [=]() {
    const RecordingInput input = RecordingFromOptions(*seq, *odometry, "--odometry");
    const RecordingsConfig config = ConfigFromOptions(*o);
    const RecordingsResult r = CloseLoops(input, config);
    PrintStages(r);
    if (config.shard_count > 0) return kExitOk;
    int accepted = 0;
    for (const LoopCandidateResult& c : r.candidates) accepted += c.verdict == "accepted";
    std::printf("%d loop closures accepted of %zu candidates; trajectory: %s/trajectory.tum\n",
                accepted, r.candidates.size(), o->out.c_str());
    if (!r.found) std::cerr << "zeroreg loops: " << r.reason << "\n";
    return kExitOk;
  };
}

}  // namespace zeroreg::cli
