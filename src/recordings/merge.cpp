// MergeRecordings and CloseLoops: keyframes, place recognition, verification, consistency and the
// pose graph wired together, with the output folder (docs/RECORDINGS.md "Merge and loops").
#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "estimate/rigid_inverse.hpp"
#include "eval/metrics.hpp"
#include "eval/prepared_cache.hpp"
#include "pipeline/prepared.hpp"
#include "recordings/keyframes.hpp"
#include "recordings/loop_consistency.hpp"
#include "recordings/place_recognition.hpp"
#include "recordings/pose_graph.hpp"
#include "recordings/report.hpp"
#include "recordings/stage_clock.hpp"
#include "viz/ply.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/recordings.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kRadiansPerDegree = M_PI / 180.0;
const char* const kRecordingNames[2] = {"A", "B"};

struct Keyframe {
  int recording = 0;
  int frame = 0;
  Transform T_before = Transform::Identity();
  double path_m = 0.0;  // along the recording's keyframes from its first
  int position = 0;     // frames of the recording before it
  Eigen::MatrixXf descriptors;
  ColoredCloud cloud;  // camera frame, thinned
};

// The loops.jsonl key of a candidate: both ends' recording and frame.
std::string PairKey(int ru, int fu, int rv, int fv) {
  return std::to_string(ru) + ":" + std::to_string(fu) + "-" + std::to_string(rv) + ":" +
         std::to_string(fv);
}

class Runner {
 public:
  Runner(std::vector<RecordingInput> inputs, const RecordingsConfig& config)
      : inputs_(std::move(inputs)), config_(config), merge_(inputs_.size() == 2) {}

  RecordingsResult Run();

 private:
  void Log(const std::string& text) const {
    if (config_.progress) std::fprintf(stderr, "zeroreg %s: %s\n", Command(), text.c_str());
  }
  const char* Command() const { return merge_ ? "merge" : "loops"; }
  std::string Name(int recording) const {
    return merge_ ? kRecordingNames[recording] : std::string("sequence");
  }
  std::string CacheKey(const Keyframe& k) const {
    return std::to_string(k.recording) + "@" + std::to_string(k.frame);
  }
  PreparedScan Prepared(const Keyframe& k);
  void SelectKeyframes(int recording);
  void ChainWithoutPoses(int recording);
  void FindCandidates();
  void Verify();
  void Decide();
  void Optimize();
  void WriteOutputs();
  json Settings() const;
  void PrepareOutDir();

  std::vector<RecordingInput> inputs_;
  RecordingsConfig config_;
  bool merge_;
  std::unique_ptr<Pipeline> pipeline_;
  std::unique_ptr<PreparedScanCache> cache_;
  std::vector<std::unique_ptr<Dataset>> datasets_;
  std::vector<Keyframe> keyframes_;
  std::vector<std::vector<int>> nodes_of_;  // per recording, keyframe indices in order
  std::vector<bool> has_poses_;
  std::map<std::string, json> resumed_;  // loops.jsonl records read back
  RecordingsResult result_;
  std::vector<int> accepted_;
  Transform T_A_B_initial_ = Transform::Identity();
  bool stop_ = false;
};

PreparedScan Runner::Prepared(const Keyframe& k) {
  return cache_->Get(CacheKey(k), [&]() {
    return pipeline_->Prepare(ScanFromView(datasets_[k.recording]->LoadFrame(k.frame)));
  });
}

json Runner::Settings() const {
  json inputs = json::array();
  for (const RecordingInput& r : inputs_) {
    inputs.push_back({{"root", r.root},
                      {"first_frame", r.first_frame},
                      {"last_frame", r.last_frame},
                      {"depth_scale", r.depth_scale},
                      {"poses", r.T_frame_camera.size()}});
  }
  json pipeline = ConfigToJson(config_.pipeline);
  pipeline.erase("threads");
  const RecordingsConfig& c = config_;
  return {{"command", Command()},
          {"recordings", inputs},
          {"pipeline", pipeline},
          {"keyframe_covisibility", c.keyframe_covisibility},
          {"keyframe_every", c.keyframe_every},
          {"vocabulary_words", c.vocabulary_words},
          {"vocabulary_seed", c.vocabulary_seed},
          {"candidates_per_keyframe", c.candidates_per_keyframe},
          {"min_separation", c.min_separation}};
}

void ReadRecords(const std::string& path, std::map<std::string, json>* records) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    try {
      const json record = json::parse(line);
      (*records)[record.at("key").get<std::string>()] = record;
    } catch (const std::exception&) {
      // A line cut short by a killed run: that candidate is verified again.
    }
  }
}

void Runner::PrepareOutDir() {
  if (!config_.pair_cache_file.empty()) ReadRecords(config_.pair_cache_file, &resumed_);
  if (config_.out_dir.empty()) return;
  fs::create_directories(config_.out_dir);
  const std::string settings_path = config_.out_dir + "/settings.json";
  const json settings = Settings();
  if (fs::exists(settings_path)) {
    std::ifstream in(settings_path);
    json old;
    try {
      in >> old;
    } catch (const std::exception&) {
      throw InputError(settings_path + ": not JSON; remove the folder or choose another --out");
    }
    if (old != settings) {
      throw InputError(config_.out_dir +
                       ": made with other recordings or settings (settings.json differs); "
                       "choose another --out or remove it");
    }
    ReadRecords(config_.out_dir + "/loops.jsonl", &resumed_);
    if (!resumed_.empty()) {
      Log("resuming " + config_.out_dir + ": " + std::to_string(resumed_.size()) +
          " verified candidates read back");
    }
  } else {
    std::ofstream out(settings_path);
    out << settings.dump(2) << "\n";
  }
}

void Runner::SelectKeyframes(int recording) {
  const RecordingInput& input = inputs_[recording];
  KeyframeConfig kc;
  kc.covisibility_threshold = config_.keyframe_covisibility;
  kc.fallback_every = config_.keyframe_every;
  ValidateKeyframeConfig(kc);
  KeyframeSelector selector(kc);
  const Dataset& dataset = *datasets_[recording];
  std::vector<int> ids;
  for (int id : dataset.FrameIds()) {
    if (id < input.first_frame) continue;
    if (input.last_frame >= input.first_frame && id > input.last_frame) break;
    ids.push_back(id);
  }
  if (ids.empty()) {
    throw InputError(input.root + ": no frames in " + std::to_string(input.first_frame) + "-" +
                     (input.last_frame >= 0 ? std::to_string(input.last_frame) : "end"));
  }
  has_poses_[recording] = !input.T_frame_camera.empty();
  int without_pose = 0;
  CloudExportConfig cloud;
  cloud.voxel_m = config_.cloud_voxel_m;
  int previous = -1;  // index of the recording's last keyframe
  for (std::size_t n = 0; n < ids.size(); ++n) {
    const int id = ids[n];
    std::optional<Transform> pose;
    if (has_poses_[recording]) {
      const auto it = input.T_frame_camera.find(id);
      if (it == input.T_frame_camera.end()) {
        ++without_pose;  // a recording with poses: a frame without one cannot be placed
        continue;
      }
      pose = it->second;
    }
    View view = dataset.LoadFrame(id);
    if (!selector.Add(view, pose)) continue;
    Keyframe k;
    k.recording = recording;
    k.frame = id;
    k.position = static_cast<int>(n);
    if (pose) k.T_before = *pose;
    if (previous >= 0 && pose) {
      const Keyframe& p = keyframes_[previous];
      k.path_m =
          p.path_m + (k.T_before.topRightCorner<3, 1>() - p.T_before.topRightCorner<3, 1>()).norm();
    }
    const Scan scan = ScanFromView(std::move(view));
    const PreparedScan prepared =
        cache_->Get(CacheKey(k), [&]() { return pipeline_->Prepare(scan); });
    const PreparedScan::Data* data = PreparedScanData(prepared);
    const LiftedFeatures& features = data->perceived->view_features.at(0);
    k.descriptors = features.features.descriptors;
    if (config_.write_cloud && !config_.out_dir.empty()) {
      k.cloud = ScanGeometry(scan, Eigen::Vector3d(0.5, 0.5, 0.5), cloud);
    }
    nodes_of_[recording].push_back(static_cast<int>(keyframes_.size()));
    keyframes_.push_back(std::move(k));
    previous = static_cast<int>(keyframes_.size()) - 1;
    if (config_.progress && nodes_of_[recording].size() % 10 == 0) {
      Log("keyframes " + Name(recording) + ": frame " + std::to_string(n + 1) + "/" +
          std::to_string(ids.size()) + ", " + std::to_string(nodes_of_[recording].size()) +
          " keyframes");
    }
  }
  if (without_pose > 0) {
    Log(Name(recording) + ": " + std::to_string(without_pose) +
        " frames have no pose in the given poses and are left out");
  }
  if (nodes_of_[recording].empty()) {
    throw InputError(input.root + ": none of the frames has a pose among the poses given");
  }
  Log("keyframes " + Name(recording) + ": " + std::to_string(nodes_of_[recording].size()) + " of " +
      std::to_string(ids.size()) + " frames");
}

// Odometry from the pair registrar for a recording without poses: consecutive keyframes
// registered, their transforms chained. A link that does not register ends the recording there.
void Runner::ChainWithoutPoses(int recording) {
  std::vector<int>& nodes = nodes_of_[recording];
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    Keyframe& previous = keyframes_[nodes[i - 1]];
    Keyframe& current = keyframes_[nodes[i]];
    const RegistrationResult r = pipeline_->Register(Prepared(current), Prepared(previous));
    if (!r.valid) {
      Log(Name(recording) + " has no poses, and keyframes at frames " +
          std::to_string(previous.frame) + " and " + std::to_string(current.frame) +
          " do not register (" + r.reason + "): the recording ends at frame " +
          std::to_string(previous.frame));
      keyframes_.resize(nodes[i]);  // the recording's keyframes are the last ones added
      nodes.resize(i);
      break;
    }
    current.T_before = previous.T_before * r.T_target_source;
    current.path_m = previous.path_m + r.T_target_source.topRightCorner<3, 1>().norm();
  }
}

void Runner::FindCandidates() {
  std::vector<Eigen::MatrixXf> sets;
  for (const Keyframe& k : keyframes_) sets.push_back(k.descriptors);
  VocabularyConfig vc;
  vc.words = config_.vocabulary_words;
  vc.seed = config_.vocabulary_seed;
  ValidateVocabularyConfig(vc);
  PlaceIndex index(Vocabulary::Train(sets, vc));
  for (const Eigen::MatrixXf& d : sets) index.Add(d);
  index.Finalize();
  for (Keyframe& k : keyframes_) k.descriptors.resize(0, 0);  // only the index needs them now
  const int k = config_.candidates_per_keyframe;
  if (merge_) {
    for (int query : nodes_of_[1]) {
      const std::vector<PlaceCandidate> ranked = index.Rank(query, nodes_of_[0], k);
      for (std::size_t r = 0; r < ranked.size(); ++r) {
        LoopCandidateResult c;
        c.u = ranked[r].id;
        c.v = query;
        c.place_score = ranked[r].score;
        c.rank = static_cast<int>(r);
        result_.candidates.push_back(c);
      }
    }
  } else {
    int rank = 0, last_u = -1;
    for (const auto& [u, v] : FarApartCandidates(index, config_.min_separation, k)) {
      LoopCandidateResult c;
      c.u = u;
      c.v = v;
      c.place_score = index.Similarity(u, v);
      rank = u == last_u ? rank + 1 : 0;
      last_u = u;
      c.rank = rank;
      result_.candidates.push_back(c);
    }
  }
  Log("place recognition: " + std::to_string(result_.candidates.size()) + " candidate pairs over " +
      std::to_string(keyframes_.size()) + " keyframes");
}

void Runner::Verify() {
  std::vector<LoopCandidateResult>& candidates = result_.candidates;
  std::ofstream loops, shared;
  if (!config_.out_dir.empty()) loops.open(config_.out_dir + "/loops.jsonl", std::ios::app);
  if (!config_.pair_cache_file.empty()) shared.open(config_.pair_cache_file, std::ios::app);
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    LoopCandidateResult& c = candidates[i];
    const Keyframe& u = keyframes_[c.u];
    const Keyframe& v = keyframes_[c.v];
    const auto it = resumed_.find(PairKey(u.recording, u.frame, v.recording, v.frame));
    if (it == resumed_.end()) {
      todo.push_back(i);
      continue;
    }
    const json& record = it->second;
    c.valid = record.at("valid").get<bool>();
    c.reason = record.at("reason").get<std::string>();
    c.path = record.at("path").get<std::string>();
    c.inliers = record.at("inliers").get<int>();
    c.overlap = record.at("overlap").get<double>();
    const json& T = record.at("T_u_v");
    for (int r = 0; r < 4; ++r) {
      for (int col = 0; col < 4; ++col) c.T_u_v(r, col) = T.at(r).at(col).get<double>();
    }
    c.resumed = true;
  }
  // Pairs sharing a keyframe next to each other, so that the cache keeps it.
  std::stable_sort(todo.begin(), todo.end(),
                   [&](std::size_t a, std::size_t b) { return candidates[a].u < candidates[b].u; });
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::exception_ptr failure;  // the first exception of any worker, rethrown after the join
  const auto work = [&]() {
    for (;;) {
      const std::size_t n = next.fetch_add(1);
      if (n >= todo.size()) return;
      LoopCandidateResult& c = candidates[todo[n]];
      const Keyframe& u = keyframes_[c.u];
      const Keyframe& v = keyframes_[c.v];
      const RegistrationResult r = pipeline_->Register(Prepared(v), Prepared(u));
      c.valid = r.valid;
      c.reason = r.reason;
      c.path = PathName(r.path);
      c.T_u_v = r.T_target_source;
      c.inliers = r.num_inliers;
      c.overlap = r.verification.overlap;
      const json record = {{"key", PairKey(u.recording, u.frame, v.recording, v.frame)},
                           {"valid", c.valid},
                           {"reason", c.reason},
                           {"path", c.path},
                           {"inliers", c.inliers},
                           {"overlap", c.overlap},
                           {"T_u_v", TransformToJson(c.T_u_v)}};
      std::lock_guard<std::mutex> lock(mutex);
      if (loops.is_open()) loops << record.dump() << "\n" << std::flush;
      if (shared.is_open()) shared << record.dump() << "\n" << std::flush;
      ++done;
      Log("verify " + std::to_string(done) + "/" + std::to_string(todo.size()) + ": " +
          Name(u.recording) + " " + std::to_string(u.frame) + " <- " + Name(v.recording) + " " +
          std::to_string(v.frame) + ": " + (c.valid ? "valid (" + c.path + ")" : "not valid"));
    }
  };
  const auto worker = [&]() {
    try {
      work();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!failure) failure = std::current_exception();
      next = todo.size();  // the other workers stop after their current pair
    }
  };
  const int jobs = std::max(1, config_.pipeline.threads);
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

void Runner::Decide() {
  std::vector<LoopClosure> loops;
  std::vector<int> candidate_of_loop;
  for (std::size_t i = 0; i < result_.candidates.size(); ++i) {
    LoopCandidateResult& c = result_.candidates[i];
    if (!c.valid) {
      c.verdict = "invalid";
      continue;
    }
    c.verdict = "inconsistent";
    loops.push_back({c.u, c.v, c.T_u_v});
    candidate_of_loop.push_back(static_cast<int>(i));
  }
  OdometryContext odometry;
  for (const Keyframe& k : keyframes_) {
    odometry.T_world_node.push_back(k.T_before);
    odometry.recording_of_node.push_back(k.recording);
    odometry.path_length_m.push_back(k.path_m);
  }
  LoopConsistencyConfig lc;
  lc.rotation_tolerance_deg = config_.consistency_rotation_deg;
  lc.translation_tolerance_m = config_.consistency_translation_m;
  lc.drift_translation_fraction = config_.drift_translation_fraction;
  lc.drift_rotation_deg_per_m = config_.drift_rotation_deg_per_m;
  ConsistentLoopSet set = SelectConsistentLoops(loops, odometry, lc);
  for (int i : set.rival) result_.candidates[candidate_of_loop[i]].verdict = "rival";
  const auto implied_by = [&](int loop) -> Transform {
    const LoopCandidateResult& c = result_.candidates[candidate_of_loop[loop]];
    const Transform T = keyframes_[c.u].T_before * c.T_u_v * RigidInverse(keyframes_[c.v].T_before);
    return T;
  };
  // Another placement of B: loop closures outside the largest set whose T_A_B lies far from its
  // own (a half turn of a symmetric place, not the noise of the same placement), of which at
  // least two agree with each other. Between two recordings that is two answers, and no test of
  // these scans tells them apart (the half turn of the cabinet's box agrees with more of the
  // depth than the truth does), so the merge refuses. Within one sequence a second set is no
  // second placement: loop closures at two places of a drifting trajectory may each agree only
  // with their neighbours.
  std::vector<int> far_rival;
  if (merge_ && set.accepted.size() >= 2) {
    std::vector<Transform> best_implied;
    for (int i : set.accepted) best_implied.push_back(implied_by(i));
    Transform best = best_implied.front();
    double best_cost = 1e300;
    for (const Transform& T : best_implied) {
      double cost = 0.0;
      for (const Transform& other : best_implied) {
        cost += TranslationErrorM(T, other) + 0.01 * RotationErrorDeg(T, other);
      }
      if (cost < best_cost) {
        best_cost = cost;
        best = T;
      }
    }
    std::vector<LoopClosure> far;
    std::vector<int> far_index;
    for (std::size_t i = 0; i < loops.size(); ++i) {
      if (std::binary_search(set.accepted.begin(), set.accepted.end(), static_cast<int>(i))) {
        continue;
      }
      const Transform T = implied_by(static_cast<int>(i));
      if (RotationErrorDeg(T, best) > config_.other_placement_deg ||
          TranslationErrorM(T, best) > config_.other_placement_m) {
        far.push_back(loops[i]);
        far_index.push_back(static_cast<int>(i));
      }
    }
    if (far.size() >= 2) {
      for (int i : SelectConsistentLoops(far, odometry, lc).accepted) {
        far_rival.push_back(far_index[i]);
      }
    }
  }
  const std::string counts = std::to_string(result_.candidates.size()) + " candidate pairs, " +
                             std::to_string(loops.size()) + " valid, the largest consistent set " +
                             std::to_string(set.accepted.size());
  if (far_rival.size() >= 2) {
    for (int i : set.accepted) result_.candidates[candidate_of_loop[i]].verdict = "ambiguous";
    for (int i : far_rival) result_.candidates[candidate_of_loop[i]].verdict = "rival";
    result_.ambiguous = true;
    result_.reason =
        "ambiguous: two placements of B are each supported by several loop closures (" +
        std::to_string(set.accepted.size()) + " and " + std::to_string(far_rival.size()) + " of " +
        counts + "); nothing accepted (a symmetric place seen from opposite sides?)";
    return;
  }
  if (static_cast<int>(set.accepted.size()) < config_.min_consistent_loops) {
    for (int i : set.accepted) result_.candidates[candidate_of_loop[i]].verdict = "too_few";
    result_.reason = std::string(merge_ ? "no overlap found" : "no loop closure found") + ": " +
                     counts + " (at least " + std::to_string(config_.min_consistent_loops) +
                     " needed)";
    return;
  }
  for (int i : set.accepted) {
    result_.candidates[candidate_of_loop[i]].verdict = "accepted";
    accepted_.push_back(candidate_of_loop[i]);
  }
  if (merge_) {
    // The initial placement of B: the accepted loop whose implied T_A_B is nearest the others.
    std::vector<Transform> implied;
    for (int i : accepted_) {
      const LoopCandidateResult& c = result_.candidates[i];
      implied.push_back(keyframes_[c.u].T_before * c.T_u_v *
                        RigidInverse(keyframes_[c.v].T_before));
    }
    double best = 1e300;
    for (const Transform& T : implied) {
      double cost = 0.0;
      for (const Transform& other : implied) {
        cost += TranslationErrorM(T, other) + 0.01 * RotationErrorDeg(T, other);
      }
      if (cost < best) {
        best = cost;
        T_A_B_initial_ = T;
      }
    }
  }
  result_.found = true;
  result_.reason = counts + " accepted" + (set.exact ? "" : " (clique search cut short)");
}

void Runner::Optimize() {
  std::vector<Transform> initial;
  for (const Keyframe& k : keyframes_) {
    initial.push_back(k.recording == 1 ? T_A_B_initial_ * k.T_before : k.T_before);
  }
  std::vector<PoseGraphEdge> edges;
  for (const std::vector<int>& nodes : nodes_of_) {
    for (std::size_t i = 1; i < nodes.size(); ++i) {
      const Keyframe& a = keyframes_[nodes[i - 1]];
      const Keyframe& b = keyframes_[nodes[i]];
      PoseGraphEdge e;
      e.from = nodes[i - 1];
      e.to = nodes[i];
      e.T_from_to = RigidInverse(a.T_before) * b.T_before;
      const double distance = e.T_from_to.topRightCorner<3, 1>().norm();
      const int frames = std::max(1, b.position - a.position);
      e.rotation_sigma_rad = config_.odometry_sigma_deg_per_frame *
                             std::sqrt(static_cast<double>(frames)) * kRadiansPerDegree;
      e.translation_sigma_m =
          0.002 + config_.odometry_sigma_fraction * distance + e.rotation_sigma_rad * distance;
      edges.push_back(e);
    }
  }
  const std::size_t odometry_edges = edges.size();
  PoseGraphResult solved;
  // Solved, then loop closures the solution contradicts dropped and solved again: the consistency
  // check compares loops two by two within tolerances that add up both loops' errors, so one loop
  // off by 10 cm can agree with every other; against the graph all of them hold, it stands out.
  for (int round = 0;; ++round) {
    edges.resize(odometry_edges);
    for (int i : accepted_) {
      const LoopCandidateResult& c = result_.candidates[i];
      PoseGraphEdge e;
      e.from = c.u;
      e.to = c.v;
      e.T_from_to = c.T_u_v;
      e.kind = PoseGraphEdge::Kind::kLoopClosure;
      e.translation_sigma_m = config_.loop_sigma_m;
      e.rotation_sigma_rad = config_.loop_sigma_deg * kRadiansPerDegree;
      edges.push_back(e);
    }
    solved = OptimizePoseGraph(initial, edges, {nodes_of_[0].front()}, PoseGraphConfig());
    std::vector<int> kept, dropped;
    for (int i : accepted_) {
      const LoopCandidateResult& c = result_.candidates[i];
      const Transform predicted = RigidInverse(solved.T_world_node[c.u]) * solved.T_world_node[c.v];
      const bool off = RotationErrorDeg(c.T_u_v, predicted) > config_.max_loop_residual_deg ||
                       TranslationErrorM(c.T_u_v, predicted) > config_.max_loop_residual_m;
      (off ? dropped : kept).push_back(i);
    }
    // Dropping stops where too few would be left to tell anything (the set stays as it is).
    if (dropped.empty() || round == 2 ||
        static_cast<int>(kept.size()) < config_.min_consistent_loops) {
      break;
    }
    for (int i : dropped) result_.candidates[i].verdict = "residual";
    Log("pose graph: " + std::to_string(dropped.size()) +
        " loop closures off the solution by more than " +
        std::to_string(config_.max_loop_residual_deg) + " deg or " +
        std::to_string(config_.max_loop_residual_m) + " m dropped");
    accepted_ = kept;
  }
  for (std::size_t n = 0; n < keyframes_.size(); ++n) {
    result_.keyframes[n].T_after = solved.T_world_node[n];
  }
  if (merge_) {
    // B's frame is where B's poses are exact: at its first pose (odometry starts there and drifts
    // away from it), so T_A_B is the move of B's first keyframe. Measured on the sessions'
    // redkitchen split: 1.0-1.9 deg off, against 1.4-3.6 deg for the mean move of all of B's
    // keyframes, which takes in B's drift and the bend the loop closures give it.
    const int first = nodes_of_[1].front();
    result_.T_A_B = solved.T_world_node[first] * RigidInverse(keyframes_[first].T_before);
  }
  Log("pose graph: " + std::to_string(keyframes_.size()) + " keyframes, " +
      std::to_string(edges.size()) + " edges, cost " + std::to_string(solved.initial_cost) +
      " -> " + std::to_string(solved.final_cost));
}

void Runner::WriteOutputs() {
  for (std::size_t r = 0; r < inputs_.size(); ++r) {
    result_.trajectories.push_back(
        PlacedTrajectory(inputs_[r].T_frame_camera, result_.keyframes, static_cast<int>(r)));
  }
  if (config_.out_dir.empty()) return;
  const std::string& dir = config_.out_dir;
  // Every candidate with its final verdict (the registrations appended during verification are
  // the resume file; this rewrite keeps them and adds the verdicts).
  {
    const std::string tmp = dir + "/loops.jsonl.tmp";
    std::ofstream out(tmp);
    for (const LoopCandidateResult& c : result_.candidates) {
      const RecordingKeyframe& u = result_.keyframes[c.u];
      const RecordingKeyframe& v = result_.keyframes[c.v];
      const json record = {
          {"key", PairKey(u.recording, u.frame, v.recording, v.frame)},
          {"u", {{"recording", Name(u.recording)}, {"frame", u.frame}, {"node", c.u}}},
          {"v", {{"recording", Name(v.recording)}, {"frame", v.frame}, {"node", c.v}}},
          {"place_score", c.place_score},
          {"rank", c.rank},
          {"valid", c.valid},
          {"reason", c.reason},
          {"path", c.path},
          {"inliers", c.inliers},
          {"overlap", c.overlap},
          {"T_u_v", TransformToJson(c.T_u_v)},
          {"verdict", c.verdict}};
      out << record.dump() << "\n";
    }
    out.close();
    fs::rename(tmp, dir + "/loops.jsonl");
  }
  {
    std::ofstream out(dir + "/keyframes.tsv");
    out << "node\trecording\tframe\n";
    for (std::size_t n = 0; n < result_.keyframes.size(); ++n) {
      out << n << "\t" << Name(result_.keyframes[n].recording) << "\t" << result_.keyframes[n].frame
          << "\n";
    }
  }
  std::vector<LogEntry> log;
  for (int i : accepted_) {
    const LoopCandidateResult& c = result_.candidates[i];
    log.push_back({c.u, c.v, static_cast<int>(result_.keyframes.size()), c.T_u_v, 0});
  }
  WriteLogFile(dir + "/loops.log", log);
  const std::string T_path = dir + "/T_A_B.txt";
  if (merge_ && result_.found) {
    std::ofstream out(T_path);
    char line[160];
    for (int r = 0; r < 4; ++r) {
      std::snprintf(line, sizeof(line), "%.9f %.9f %.9f %.9f\n", result_.T_A_B(r, 0),
                    result_.T_A_B(r, 1), result_.T_A_B(r, 2), result_.T_A_B(r, 3));
      out << line;
    }
  } else if (merge_) {
    fs::remove(T_path);  // a resumed folder must not keep an earlier answer
  }
  if (merge_) {
    if (result_.found) {
      WriteTumTrajectory(dir + "/trajectory_A.tum", result_.trajectories[0]);
      WriteTumTrajectory(dir + "/trajectory_B.tum", result_.trajectories[1]);
    }
  } else {
    WriteTumTrajectory(dir + "/trajectory.tum", result_.trajectories[0]);
  }
  if (config_.write_cloud && (result_.found || !merge_)) {
    ColoredCloud all;
    for (std::size_t n = 0; n < keyframes_.size(); ++n) {
      const Transform& T = result_.keyframes[n].T_after;
      for (std::size_t p = 0; p < keyframes_[n].cloud.points.size(); ++p) {
        all.points.push_back(T.topLeftCorner<3, 3>() * keyframes_[n].cloud.points[p] +
                             T.topRightCorner<3, 1>());
        all.colors.push_back(keyframes_[n].cloud.colors[p]);
      }
    }
    WritePly(dir + "/merged.ply", VoxelDownsample(all, config_.cloud_voxel_m));
  }
  if (config_.write_report) {
    WriteRecordingsReport(dir + "/report.html", result_, merge_, T_A_B_initial_);
  }
}

RecordingsResult Runner::Run() {
  if (config_.candidates_per_keyframe < 1 || config_.min_separation < 1 ||
      config_.min_consistent_loops < 1 || !(config_.cloud_voxel_m > 0) ||
      !(config_.loop_sigma_deg > 0) || !(config_.loop_sigma_m > 0) ||
      !(config_.odometry_sigma_deg_per_frame > 0) || !(config_.odometry_sigma_fraction >= 0)) {
    throw InputError(
        "recordings config: candidates_per_keyframe, min_separation, min_consistent_loops, "
        "cloud_voxel_m and the loop and odometry sigmas must be positive");
  }
  PrepareOutDir();
  has_poses_.assign(inputs_.size(), false);
  nodes_of_.assign(inputs_.size(), {});
  for (const RecordingInput& input : inputs_) {
    DatasetOptions options;
    options.depth_scale = input.depth_scale;
    datasets_.push_back(OpenDataset(input.root, options));
  }
  {
    StageClock clock("load_models", &result_.stages);
    pipeline_ = std::make_unique<Pipeline>(config_.pipeline);
    cache_ = std::make_unique<PreparedScanCache>(1 << 20, config_.prepared_budget_bytes);
  }
  {
    StageClock clock("keyframes", &result_.stages);
    for (std::size_t r = 0; r < inputs_.size(); ++r) {
      SelectKeyframes(static_cast<int>(r));
      if (!has_poses_[r]) ChainWithoutPoses(static_cast<int>(r));
    }
  }
  for (const Keyframe& k : keyframes_) {
    result_.keyframes.push_back({k.recording, k.frame, k.T_before, k.T_before});
  }
  {
    StageClock clock("place_recognition", &result_.stages);
    FindCandidates();
  }
  {
    StageClock clock("verification", &result_.stages);
    Verify();
  }
  {
    StageClock clock("consistency", &result_.stages);
    Decide();
  }
  Log(result_.reason);
  if (result_.found) {
    StageClock clock("optimisation", &result_.stages);
    Optimize();
  }
  {
    StageClock clock("outputs", &result_.stages);
    WriteOutputs();
  }
  if (!config_.out_dir.empty()) {
    json stages = json::array();
    for (const StageReport& s : result_.stages) {
      stages.push_back(
          {{"stage", s.stage}, {"seconds", s.seconds}, {"peak_rss_mib", s.peak_rss_mib}});
    }
    json summary = {{"found", result_.found},
                    {"reason", result_.reason},
                    {"ambiguous", result_.ambiguous},
                    {"keyframes", result_.keyframes.size()},
                    {"candidates", result_.candidates.size()},
                    {"accepted", accepted_.size()},
                    {"stages", stages}};
    if (merge_ && result_.found) summary["T_A_B"] = TransformToJson(result_.T_A_B);
    std::ofstream out(config_.out_dir + "/summary.json");
    out << summary.dump(2) << "\n";
  }
  return result_;
}

}  // namespace

nlohmann::json RecordingsResultToJson(const RecordingsResult& r) {
  json keyframes = json::array(), candidates = json::array(), stages = json::array(),
       trajectories = json::array();
  for (const RecordingKeyframe& k : r.keyframes) {
    keyframes.push_back({{"recording", k.recording},
                         {"frame", k.frame},
                         {"T_before", TransformToJson(k.T_before)},
                         {"T_after", TransformToJson(k.T_after)}});
  }
  for (const LoopCandidateResult& c : r.candidates) {
    candidates.push_back({{"u", c.u},
                          {"v", c.v},
                          {"place_score", c.place_score},
                          {"rank", c.rank},
                          {"valid", c.valid},
                          {"reason", c.reason},
                          {"path", c.path},
                          {"T_u_v", TransformToJson(c.T_u_v)},
                          {"inliers", c.inliers},
                          {"overlap", c.overlap},
                          {"verdict", c.verdict},
                          {"resumed", c.resumed}});
  }
  for (const StageReport& s : r.stages) {
    stages.push_back(
        {{"stage", s.stage}, {"seconds", s.seconds}, {"peak_rss_mib", s.peak_rss_mib}});
  }
  for (const auto& trajectory : r.trajectories) {
    json t = json::object();
    for (const auto& [id, T] : trajectory) t[std::to_string(id)] = TransformToJson(T);
    trajectories.push_back(t);
  }
  return {{"found", r.found},
          {"reason", r.reason},
          {"ambiguous", r.ambiguous},
          {"T_A_B", TransformToJson(r.T_A_B)},
          {"keyframes", keyframes},
          {"candidates", candidates},
          {"trajectories", trajectories},
          {"stages", stages}};
}

void ApplyRecordingsOptions(const nlohmann::json& options, const std::string& where,
                            RecordingsConfig* config) {
  if (!options.is_object()) throw InputError(where + ": expected an object of options");
  for (const auto& [key, value] : options.items()) {
    const std::string name = where + "." + key;
    const auto number = [&]() {
      if (!value.is_number()) throw InputError(name + ": expected a number");
      return value.get<double>();
    };
    const auto integer = [&]() {
      if (!value.is_number_integer()) throw InputError(name + ": expected an integer");
      return value.get<long long>();
    };
    const auto boolean = [&]() {
      if (!value.is_boolean()) throw InputError(name + ": expected true or false");
      return value.get<bool>();
    };
    if (key == "keyframe_covisibility") {
      config->keyframe_covisibility = number();
    } else if (key == "keyframe_every") {
      config->keyframe_every = static_cast<int>(integer());
    } else if (key == "vocabulary_words") {
      config->vocabulary_words = static_cast<int>(integer());
    } else if (key == "vocabulary_seed") {
      config->vocabulary_seed = static_cast<std::uint64_t>(integer());
    } else if (key == "candidates_per_keyframe") {
      config->candidates_per_keyframe = static_cast<int>(integer());
    } else if (key == "min_separation") {
      config->min_separation = static_cast<int>(integer());
    } else if (key == "min_consistent_loops") {
      config->min_consistent_loops = static_cast<int>(integer());
    } else if (key == "prepared_budget_mib") {
      const long long mib = integer();
      if (mib < 16) throw InputError(name + ": expected at least 16");
      config->prepared_budget_bytes = static_cast<std::size_t>(mib) << 20;
    } else if (key == "cloud_voxel_m") {
      config->cloud_voxel_m = number();
    } else if (key == "progress") {
      config->progress = boolean();
    } else if (key == "write_cloud") {
      config->write_cloud = boolean();
    } else if (key == "write_report") {
      config->write_report = boolean();
    } else {
      throw InputError(name + ": unknown option (docs/RECORDINGS.md lists them)");
    }
  }
}

RecordingsResult MergeRecordings(const RecordingInput& a, const RecordingInput& b,
                                 const RecordingsConfig& config) {
  Runner runner({a, b}, config);
  return runner.Run();
}

RecordingsResult CloseLoops(const RecordingInput& sequence, const RecordingsConfig& config) {
  Runner runner({sequence}, config);
  RecordingsResult result = runner.Run();
  return result;
}

}  // namespace zeroreg
