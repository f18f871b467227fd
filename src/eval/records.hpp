// One evaluated pair: what to register (PairTask) and what came out of it (PairRecord), with the
// per-pair metrics of DESIGN §6 and their JSON-lines form (`<out>/pairs.jsonl`).
//
// Convention (types.hpp): a pair is (target i, source j); the estimate scored is T_target_source,
// which for 3DMatch is the gt.log entry "i j" = T_i_j (maps fragment j into fragment i).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

using InformationMatrix = Eigen::Matrix<double, 6, 6>;

// 3DMatch success threshold on the registration-recall error E (RMSE 0.2 m, squared).
constexpr double kRecallErrorThreshold = 0.2 * 0.2;
// 3DMatch inlier-ratio distance and feature-match-recall threshold.
constexpr double kInlierDistanceM = 0.1;
constexpr double kFeatureMatchRecallThreshold = 0.05;
// A matched object pair is correct when its centroids agree within this under the ground truth
// (partly seen objects shift their centroid by up to a few decimetres).
constexpr double kObjectMatchToleranceM = 0.3;

struct PairTask {
  std::string benchmark;  // "3DMatch", "3DLoMatch" or "frames"
  std::string scene;      // e.g. "7-scenes-redkitchen"
  int target_id = 0;      // i: fragment or frame id of the target
  int source_id = 0;      // j: fragment or frame id of the source
  // How to load the scans (see ScanLoader in runner.hpp): a scan.json path or DIR@N.
  std::string target_ref, source_ref;
  // Ground truth T_target_source: the gt.log entry; for frames, left empty and taken from the
  // frames' poses when the scans are loaded.
  std::optional<Transform> T_target_source_gt;
  std::optional<InformationMatrix> information;  // gt.info entry (3DMatch protocol only)
  int log_n = 0;             // the "n" of the gt.log header (fragments in the scene)
  bool consecutive = false;  // 3DMatch j == i + 1: registered but not counted in the recall

  // "benchmark/scene i j", unique within a run; pairs.jsonl is keyed by it.
  std::string Key() const;
};

struct PairRecord {
  std::string key, benchmark, scene, method;
  int target_id = 0, source_id = 0, log_n = 0;
  bool consecutive = false;
  bool valid = false;  // the method's own verdict
  std::string reason;
  std::string path;  // e.g. "object", "image", "image-fallback" (zeroreg); "fpfh"
  // Set when the pair could not be run (an exception); such records are re-run on resume.
  std::string error;
  // The estimate exactly as est.log stores it (rounded to its 9 significant digits), so that an
  // independent scorer reading est.log decides every pair the same way.
  Transform T_est = Transform::Identity();
  Transform T_gt = Transform::Identity();
  double rotation_error_deg = 0.0;  // vs the orthonormalised GT rotation
  double translation_error_m = 0.0;
  std::optional<double> recall_error;  // 3DMatch E (needs gt.info)
  bool registered = false;             // recall_error <= kRecallErrorThreshold
  double inlier_ratio = 0.0;  // the method's correspondences within 0.1 m under the GT pose
  int num_correspondences = 0;
  int num_inliers = 0;   // the method's own inliers (RANSAC)
  double time_ms = 0.0;  // registration only (scan loading excluded)
  // Object level (zeroreg's object path; 0 for other methods): objects of each scan, its views,
  // matched object pairs and those whose centroids agree within kObjectMatchToleranceM under
  // T_gt (CountCorrectObjectMatches).
  int objects_source = 0, objects_target = 0, views_source = 0, views_target = 0;
  int object_matches = 0, object_matches_correct = 0;
  // Of the matched pairs, those whose visible surfaces coincide under T_gt (SameSurface,
  // eval/object_match_metrics.hpp); -1 when the method gave no object surfaces.
  int object_matches_same_surface = -1;
  // The most right matches the objects allow (CountMatchableObjectPairs): one-to-one pairs of
  // equal labels whose centroids agree within kObjectMatchToleranceM under T_gt, and those whose
  // surfaces coincide under it (SameSurface); -1 when the method gave no object labels (resp.
  // surfaces).
  int object_pairs_matchable = -1;
  int object_pairs_matchable_same_surface = -1;
};

// Rounds every entry like WriteLogFile's "%15.8e" does.
Transform RoundLikeLogFile(const Transform& T);

// What a method returns for one pair (see methods.hpp).
struct MethodOutput {
  Transform T_target_source = Transform::Identity();
  bool valid = false;
  std::string reason;
  std::string path;  // which correspondence source produced it (RegistrationResult::path)
  std::vector<Correspondence> correspondences;  // for the inlier ratio under the GT pose
  int num_inliers = 0;
  // zeroreg only: the object level's result (empty for other methods).
  std::vector<Eigen::Vector3d> source_object_centroids, target_object_centroids;
  std::vector<std::pair<int, int>> object_matches;  // (source row, target row)
  // Per object, its label (for the matchable pairs); empty when the method has none.
  std::vector<std::string> source_object_labels, target_object_labels;
  // Per object, its surface points in the scan frame (ObjectSummary::points), for the surface
  // measure of the object matches; empty when the method has none.
  std::vector<std::vector<Eigen::Vector3d>> source_object_surfaces, target_object_surfaces;
  int views_source = 0, views_target = 0;
};

// Computes the per-pair metrics of DESIGN §6 for `output` against `T_gt`.
PairRecord ScorePair(const PairTask& task, const std::string& method, const MethodOutput& output,
                     const Transform& T_gt, double time_ms);

// Identity fields only (key, benchmark, scene, ids, consecutive): what run.json keeps of the
// selection so that summaries and merges can be recomputed without the data.
nlohmann::json PairTaskToJson(const PairTask& task);
PairTask PairTaskFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json PairRecordToJson(const PairRecord& record);
// Throws InputError naming `where` when a field is missing or has the wrong type.
PairRecord PairRecordFromJson(const nlohmann::json& json, const std::string& where);

// Reads a pairs.jsonl file: one record per line, later lines win for the same key (in the place
// of its first line); `*superseded` counts the lines a later one replaced. A missing file gives no
// records. A truncated last line (a run killed while writing) is ignored and reported in
// `*dropped_last_line`; any other malformed line throws InputError naming the file and line.
std::vector<PairRecord> ReadPairsJsonl(const std::string& path, bool* dropped_last_line = nullptr,
                                       int* superseded = nullptr);
// Rewrites `path` with exactly `records`, one line each.
void WritePairsJsonl(const std::string& path, const std::vector<PairRecord>& records);

}  // namespace zeroreg
