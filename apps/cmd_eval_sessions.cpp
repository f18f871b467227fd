// `zeroreg eval sessions`: the protocol of ../shared/sessions (README there) run through
// MergeRecordings per split, mode and seed, with the errors against the ground truth
// (docs/RECORDINGS.md "eval sessions").
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "estimate/rigid_inverse.hpp"
#include "eval/metrics.hpp"
#include "eval/sessions_protocol.hpp"
#include "recording_options.hpp"
#include "recordings/keyframes.hpp"
#include "recordings/open3d_baseline.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct SessionsOptions {
  std::string sessions = "../shared/sessions/sessions.tsv", data = "../shared/data";
  std::vector<std::string> scenes, modes = {"unaligned", "drift"};
  std::string seeds = "0-2";
  // zeroreg: MergeRecordings; open3d-multiway: Open3D's multiway registration recipe on the same
  // keyframes (src/recordings/open3d_baseline.hpp), the baseline.
  std::string method = "zeroreg";
  RecordingsOptions recordings;
};

struct Split {
  std::string scene;
  int a_first = 0, a_last = 0, b_first = 0, b_last = 0;
};

std::pair<int, int> Range(const std::string& text, const std::string& where) {
  int first = 0, last = 0;
  char dash = 0;
  std::istringstream in(text);
  if (!(in >> first >> dash >> last) || dash != '-' || last < first) {
    throw InputError(where + ": '" + text + "': expected a range FIRST-LAST");
  }
  return {first, last};
}

std::vector<Split> ReadSplits(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the sessions list (scene<TAB>A<TAB>B)");
  std::vector<Split> out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#' || line.rfind("scene", 0) == 0) continue;
    std::istringstream fields(line);
    std::string scene, a, b;
    if (!std::getline(fields, scene, '\t') || !std::getline(fields, a, '\t') ||
        !std::getline(fields, b, '\t')) {
      throw InputError(path + ":" + std::to_string(number) + ": expected scene<TAB>A<TAB>B");
    }
    Split s{scene};
    std::tie(s.a_first, s.a_last) = Range(a, path + ":" + std::to_string(number));
    std::tie(s.b_first, s.b_last) = Range(b, path + ":" + std::to_string(number));
    out.push_back(s);
  }
  return out;
}

// One split, mode and seed: the merge and its errors.
json RunOne(const SessionsOptions& o, const Split& split, const std::string& mode, int seed,
            const std::string& dir) {
  const std::string root = o.data + "/" + split.scene;
  RecordingInput a = ParseRecordingSpec(root + "@" + std::to_string(split.a_first) + "-" +
                                        std::to_string(split.a_last));
  RecordingInput b = ParseRecordingSpec(root + "@" + std::to_string(split.b_first) + "-" +
                                        std::to_string(split.b_last));
  const std::map<int, Transform> truth_a = GroundTruthPoses(a), truth_b = GroundTruthPoses(b);
  if (truth_a.empty() || truth_b.empty()) throw InputError(root + ": no ground-truth poses");
  const Transform T_Bframe_world = SeededUnalignment(static_cast<std::uint64_t>(seed));
  const bool drift = mode == "drift";
  const std::map<int, Transform> given_a =
      drift ? DriftedOdometry(truth_a, 1000u * seed + 1) : truth_a;
  const std::map<int, Transform> given_b_world =
      drift ? DriftedOdometry(truth_b, 1000u * seed + 2) : truth_b;
  a.T_frame_camera = given_a;
  b.T_frame_camera = Moved(T_Bframe_world, given_b_world);
  RecordingsConfig config = ConfigFromOptions(o.recordings);
  config.out_dir = dir;
  // Pair registrations do not depend on the poses: shared by every seed and mode of the split.
  config.pair_cache_file = fs::path(dir).parent_path().string() + "/pairs-cache.jsonl";
  const RecordingsResult r = o.method == "open3d-multiway" ? MergeWithOpen3dMultiway(a, b, config)
                                                           : MergeRecordings(a, b, config);

  json row = {{"scene", split.scene}, {"method", o.method}, {"mode", mode},
              {"seed", seed},         {"found", r.found},   {"reason", r.reason}};
  const Transform T_A_B_true = RigidInverse(T_Bframe_world);
  row["ate_a_before_cm"] = 100.0 * AbsoluteTrajectoryError(given_a, truth_a);
  row["ate_b_before_cm"] = 100.0 * AbsoluteTrajectoryError(given_b_world, truth_b);
  if (r.found) {
    row["rot_err_deg"] = RotationErrorDeg(r.T_A_B, T_A_B_true);
    row["trans_err_cm"] = 100.0 * TranslationErrorM(r.T_A_B, T_A_B_true);
    row["ate_a_after_cm"] = 100.0 * AbsoluteTrajectoryError(r.trajectories[0], truth_a);
    row["ate_b_after_cm"] = 100.0 * AbsoluteTrajectoryError(r.trajectories[1], truth_b);
  }
  // Loop closures against the truth: right within 5 deg / 10 cm; recall over the co-visible
  // keyframe pairs (symmetric co-visibility >= 0.3 under the truth) between A and B.
  const auto truth = [&](const RecordingKeyframe& k) {
    return k.recording == 0 ? truth_a.at(k.frame) : truth_b.at(k.frame);
  };
  int accepted = 0, wrong = 0, valid = 0, valid_wrong = 0;
  std::set<std::pair<int, int>> accepted_right;
  for (const LoopCandidateResult& c : r.candidates) {
    const Transform T_true = RigidInverse(truth(r.keyframes[c.u])) * truth(r.keyframes[c.v]);
    const bool right =
        RotationErrorDeg(c.T_u_v, T_true) <= 5.0 && TranslationErrorM(c.T_u_v, T_true) <= 0.10;
    valid += c.valid;
    valid_wrong += c.valid && !right;
    if (c.verdict == "accepted") {
      ++accepted;
      wrong += !right;
      if (right) accepted_right.insert({c.u, c.v});
    }
  }
  DatasetOptions options;
  const auto dataset = OpenDataset(root, options);
  std::vector<View> views;
  for (const RecordingKeyframe& k : r.keyframes) {
    View v = dataset->LoadFrame(k.frame);
    v.color = cv::Mat();
    views.push_back(std::move(v));
  }
  int covisible = 0, found_covisible = 0, queries = 0, query_hits = 0;
  std::set<std::pair<int, int>> candidate_pairs;
  for (const LoopCandidateResult& c : r.candidates) candidate_pairs.insert({c.u, c.v});
  for (std::size_t v = 0; v < r.keyframes.size(); ++v) {
    if (r.keyframes[v].recording != 1) continue;
    bool any = false, hit = false;
    for (std::size_t u = 0; u < r.keyframes.size(); ++u) {
      if (r.keyframes[u].recording != 0) continue;
      const double c =
          Covisibility(views[u], truth(r.keyframes[u]), views[v], truth(r.keyframes[v]));
      if (c < 0.3) continue;
      any = true;
      ++covisible;
      const std::pair<int, int> key{static_cast<int>(u), static_cast<int>(v)};
      found_covisible += accepted_right.count(key);
      hit = hit || candidate_pairs.count(key);
    }
    queries += any;
    query_hits += hit;
  }
  row["keyframes"] = r.keyframes.size();
  row["candidates"] = r.candidates.size();
  row["valid"] = valid;
  row["valid_wrong"] = valid_wrong;
  row["accepted"] = accepted;
  row["accepted_wrong"] = wrong;
  row["loop_precision"] = accepted ? double(accepted - wrong) / accepted : 1.0;
  row["covisible_pairs"] = covisible;
  row["loop_recall"] = covisible ? double(found_covisible) / covisible : 0.0;
  row["place_queries"] = queries;
  row["place_recall_at_candidates"] = queries ? double(query_hits) / queries : 0.0;
  json stages = json::object();
  double peak = 0.0, total = 0.0;
  for (const StageReport& s : r.stages) {
    stages[s.stage] = {{"seconds", s.seconds}, {"peak_rss_mib", s.peak_rss_mib}};
    peak = std::max(peak, s.peak_rss_mib);
    total += s.seconds;
  }
  row["stages"] = stages;
  row["seconds"] = total;
  row["peak_rss_mib"] = peak;
  return row;
}

std::string Cell(const json& row, const char* key, const char* format) {
  if (!row.contains(key) || row[key].is_null()) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, row[key].get<double>());
  return buffer;
}

int RunSessions(const SessionsOptions& o) {
  std::pair<int, int> seeds = Range(o.seeds, "--seeds");
  for (const std::string& mode : o.modes) {
    if (mode != "unaligned" && mode != "drift") {
      throw InputError("--modes " + mode + ": expected unaligned and/or drift");
    }
  }
  std::vector<Split> splits;
  for (const Split& s : ReadSplits(o.sessions)) {
    if (o.scenes.empty() ||
        std::find(o.scenes.begin(), o.scenes.end(), s.scene) != o.scenes.end()) {
      splits.push_back(s);
    }
  }
  if (splits.empty()) throw InputError("--scene: none of the given scenes is in " + o.sessions);
  fs::create_directories(o.recordings.out);
  std::vector<json> rows;
  for (const Split& split : splits) {
    for (const std::string& mode : o.modes) {
      for (int seed = seeds.first; seed <= seeds.second; ++seed) {
        const std::string dir =
            o.recordings.out + "/" + split.scene + "/" + mode + "-seed" + std::to_string(seed);
        const std::string eval_path = dir + "/eval.json";
        json row;
        if (fs::exists(eval_path)) {
          std::ifstream in(eval_path);
          in >> row;
        } else {
          std::fprintf(stderr, "zeroreg eval sessions: %s %s seed %d\n", split.scene.c_str(),
                       mode.c_str(), seed);
          row = RunOne(o, split, mode, seed, dir);
          std::ofstream out(eval_path);
          out << row.dump(2) << "\n";
        }
        rows.push_back(row);
      }
    }
  }
  std::ofstream md(o.recordings.out + "/summary.md");
  std::ofstream jsonl(o.recordings.out + "/sessions.jsonl");
  const char* header =
      "| scene | mode | seed | found | T_A_B rot deg | T_A_B trans cm | ATE A before/after cm | "
      "ATE B before/after cm | accepted (wrong) | loop precision | loop recall | place recall@k | "
      "time s | peak RSS MiB |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  md << header;
  std::cout << header;
  for (const json& row : rows) {
    jsonl << row.dump() << "\n";
    char line[1024];
    std::snprintf(
        line, sizeof(line),
        "| %s | %s | %d | %s | %s | %s | %s / %s | %s / %s | %d (%d) | %s | %s | %s | %s | "
        "%s |\n",
        row["scene"].get<std::string>().c_str(), row["mode"].get<std::string>().c_str(),
        row["seed"].get<int>(), row["found"].get<bool>() ? "yes" : "no",
        Cell(row, "rot_err_deg", "%.2f").c_str(), Cell(row, "trans_err_cm", "%.1f").c_str(),
        Cell(row, "ate_a_before_cm", "%.1f").c_str(), Cell(row, "ate_a_after_cm", "%.1f").c_str(),
        Cell(row, "ate_b_before_cm", "%.1f").c_str(), Cell(row, "ate_b_after_cm", "%.1f").c_str(),
        row["accepted"].get<int>(), row["accepted_wrong"].get<int>(),
        Cell(row, "loop_precision", "%.2f").c_str(), Cell(row, "loop_recall", "%.2f").c_str(),
        Cell(row, "place_recall_at_candidates", "%.2f").c_str(),
        Cell(row, "seconds", "%.0f").c_str(), Cell(row, "peak_rss_mib", "%.0f").c_str());
    md << line;
    std::cout << line;
  }
  return kExitOk;
}

}  // namespace

CLI::App* AddEvalSessionsCommand(CLI::App& eval, Runner* run) {
  auto o = std::make_shared<SessionsOptions>();
  CLI::App* app = eval.add_subcommand(
      "sessions",
      "merge the two recordings of each split of ../shared/sessions (seeded unalignment and "
      "drift) and measure T_A_B, ATE and the loop closures");
  app->add_option("--sessions", o->sessions, "splits: scene<TAB>A<TAB>B (frame ranges)")
      ->capture_default_str();
  app->add_option("--data,-d", o->data, "folder of the scenes")->capture_default_str();
  app->add_option("--scene", o->scenes, "only these scenes (repeatable)");
  app->add_option("--modes", o->modes,
                  "unaligned (ground-truth poses, B in a frame of its own) "
                  "and/or drift (drifted odometry too)")
      ->delimiter(',')
      ->capture_default_str();
  app->add_option("--seeds", o->seeds, "seeds FIRST-LAST")->capture_default_str();
  app->add_option("--method", o->method,
                  "zeroreg, or open3d-multiway (Open3D's multiway registration recipe on the same "
                  "keyframes: FPFH + RANSAC + ICP between every keyframe pair, its pose graph)")
      ->check(CLI::IsMember({"zeroreg", "open3d-multiway"}))
      ->capture_default_str();
  AddRecordingsOptions(*app, &o->recordings);
  *run = [o]() { return RunSessions(*o); };
  return app;
}

}  // namespace zeroreg::cli
