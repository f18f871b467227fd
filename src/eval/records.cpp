#include "eval/records.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>

#include "eval/metrics.hpp"
#include "eval/object_match_metrics.hpp"
#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;

Transform TransformFromJson(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 4) {
    throw MakeInputError(where, "expected a 4x4 matrix as 4 rows of 4 numbers");
  }
  Transform T;
  for (int r = 0; r < 4; ++r) {
    if (!j[r].is_array() || j[r].size() != 4) {
      throw MakeInputError(where, "expected a 4x4 matrix as 4 rows of 4 numbers");
    }
    for (int c = 0; c < 4; ++c) {
      if (!j[r][c].is_number()) throw MakeInputError(where, "matrix entry is not a number");
      T(r, c) = j[r][c].get<double>();
    }
  }
  return T;
}

template <typename T>
T Get(const json& j, const char* key, const std::string& where) {
  if (!j.contains(key)) throw MakeInputError(where, std::string("missing field '") + key + "'");
  try {
    return j.at(key).get<T>();
  } catch (const json::exception&) {
    throw MakeInputError(where, std::string("field '") + key + "' has the wrong type");
  }
}

}  // namespace

std::string PairTask::Key() const {
  return benchmark + "/" + scene + " " + std::to_string(target_id) + " " +
         std::to_string(source_id);
}

Transform RoundLikeLogFile(const Transform& T) {
  Transform rounded;
  char text[64];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(text, sizeof(text), "%15.8e", T(r, c));
      rounded(r, c) = std::strtod(text, nullptr);
    }
  }
  return rounded;
}

PairRecord ScorePair(const PairTask& task, const std::string& method, const MethodOutput& output,
                     const Transform& T_gt, double time_ms) {
  PairRecord r;
  r.key = task.Key();
  r.benchmark = task.benchmark;
  r.scene = task.scene;
  r.method = method;
  r.target_id = task.target_id;
  r.source_id = task.source_id;
  r.log_n = task.log_n;
  r.consecutive = task.consecutive;
  r.valid = output.valid;
  r.reason = output.reason;
  r.path = output.path;
  r.T_est = RoundLikeLogFile(output.T_target_source);
  r.T_gt = T_gt;
  r.rotation_error_deg = RotationErrorDeg(r.T_est, T_gt);
  r.translation_error_m = TranslationErrorM(r.T_est, T_gt);
  if (task.information) {
    r.recall_error = RegistrationRecallError(r.T_est, T_gt, *task.information);
    r.registered = *r.recall_error <= kRecallErrorThreshold;
  }
  r.inlier_ratio = CorrespondenceInlierRatio(output.correspondences, T_gt, kInlierDistanceM);
  r.num_correspondences = static_cast<int>(output.correspondences.size());
  r.num_inliers = output.num_inliers;
  r.time_ms = time_ms;
  r.objects_source = static_cast<int>(output.source_object_centroids.size());
  r.objects_target = static_cast<int>(output.target_object_centroids.size());
  r.views_source = output.views_source;
  r.views_target = output.views_target;
  // The two tests of an object pair under the ground truth: centroids within
  // kObjectMatchToleranceM, and visible surfaces that coincide (SameSurface).
  const auto centroids_agree = [&](int s, int t) {
    const Eigen::Vector3d moved =
        (T_gt * output.source_object_centroids[static_cast<std::size_t>(s)].homogeneous())
            .head<3>();
    return (moved - output.target_object_centroids[static_cast<std::size_t>(t)]).norm() <
           kObjectMatchToleranceM;
  };
  const auto surfaces_coincide = [&](int s, int t) {
    return SameSurface(output.source_object_surfaces[static_cast<std::size_t>(s)],
                       output.target_object_surfaces[static_cast<std::size_t>(t)], T_gt);
  };
  const bool have_surfaces =
      output.source_object_surfaces.size() == output.source_object_centroids.size() &&
      output.target_object_surfaces.size() == output.target_object_centroids.size();
  if (have_surfaces && !output.object_matches.empty()) r.object_matches_same_surface = 0;
  for (const auto& [s, t] : output.object_matches) {
    if (s < 0 || t < 0 || s >= r.objects_source || t >= r.objects_target) continue;
    ++r.object_matches;
    if (centroids_agree(s, t)) ++r.object_matches_correct;
    if (have_surfaces && surfaces_coincide(s, t)) ++r.object_matches_same_surface;
  }
  const bool have_labels =
      output.source_object_labels.size() == output.source_object_centroids.size() &&
      output.target_object_labels.size() == output.target_object_centroids.size() &&
      r.objects_source + r.objects_target > 0;
  if (have_labels) {
    const MatchableObjects objects{output.source_object_labels, output.target_object_labels};
    r.object_pairs_matchable = CountMatchableObjectPairs(objects, centroids_agree);
    if (have_surfaces) {
      r.object_pairs_matchable_same_surface = CountMatchableObjectPairs(objects, surfaces_coincide);
    }
  }
  return r;
}

json PairTaskToJson(const PairTask& t) {
  return {{"key", t.Key()},        {"benchmark", t.benchmark}, {"scene", t.scene},
          {"target", t.target_id}, {"source", t.source_id},    {"consecutive", t.consecutive}};
}

PairTask PairTaskFromJson(const json& j, const std::string& where) {
  if (!j.is_object()) throw MakeInputError(where, "expected a pair object");
  PairTask t;
  t.benchmark = Get<std::string>(j, "benchmark", where);
  t.scene = Get<std::string>(j, "scene", where);
  t.target_id = Get<int>(j, "target", where);
  t.source_id = Get<int>(j, "source", where);
  t.consecutive = Get<bool>(j, "consecutive", where);
  return t;
}

json PairRecordToJson(const PairRecord& r) {
  json j{{"key", r.key},
         {"benchmark", r.benchmark},
         {"scene", r.scene},
         {"target", r.target_id},
         {"source", r.source_id},
         {"log_n", r.log_n},
         {"consecutive", r.consecutive},
         {"method", r.method},
         {"valid", r.valid},
         {"reason", r.reason},
         {"path", r.path},
         {"T_est", TransformToJson(r.T_est)},
         {"T_gt", TransformToJson(r.T_gt)},
         {"rotation_error_deg", r.rotation_error_deg},
         {"translation_error_m", r.translation_error_m},
         {"registered", r.registered},
         {"inlier_ratio", r.inlier_ratio},
         {"num_correspondences", r.num_correspondences},
         {"num_inliers", r.num_inliers},
         {"time_ms", r.time_ms}};
  if (r.objects_source + r.objects_target + r.object_matches > 0) {
    j["objects"] = {{"source", r.objects_source},     {"target", r.objects_target},
                    {"views_source", r.views_source}, {"views_target", r.views_target},
                    {"matches", r.object_matches},    {"correct", r.object_matches_correct}};
    if (r.object_matches_same_surface >= 0)
      j["objects"]["same_surface"] = r.object_matches_same_surface;
    if (r.object_pairs_matchable >= 0) j["objects"]["matchable"] = r.object_pairs_matchable;
    if (r.object_pairs_matchable_same_surface >= 0)
      j["objects"]["matchable_same_surface"] = r.object_pairs_matchable_same_surface;
  }
  if (r.recall_error) j["recall_error"] = *r.recall_error;
  if (!r.error.empty()) j["error"] = r.error;
  return j;
}

PairRecord PairRecordFromJson(const json& j, const std::string& where) {
  if (!j.is_object()) throw MakeInputError(where, "expected a JSON object per line");
  PairRecord r;
  r.key = Get<std::string>(j, "key", where);
  r.benchmark = Get<std::string>(j, "benchmark", where);
  r.scene = Get<std::string>(j, "scene", where);
  r.target_id = Get<int>(j, "target", where);
  r.source_id = Get<int>(j, "source", where);
  r.log_n = Get<int>(j, "log_n", where);
  r.consecutive = Get<bool>(j, "consecutive", where);
  r.method = Get<std::string>(j, "method", where);
  r.valid = Get<bool>(j, "valid", where);
  r.reason = Get<std::string>(j, "reason", where);
  if (j.contains("path")) r.path = Get<std::string>(j, "path", where);
  if (j.contains("error")) r.error = Get<std::string>(j, "error", where);
  r.T_est = TransformFromJson(j.value("T_est", json()), where + " T_est");
  r.T_gt = TransformFromJson(j.value("T_gt", json()), where + " T_gt");
  r.rotation_error_deg = Get<double>(j, "rotation_error_deg", where);
  r.translation_error_m = Get<double>(j, "translation_error_m", where);
  if (j.contains("recall_error")) r.recall_error = Get<double>(j, "recall_error", where);
  r.registered = Get<bool>(j, "registered", where);
  r.inlier_ratio = Get<double>(j, "inlier_ratio", where);
  r.num_correspondences = Get<int>(j, "num_correspondences", where);
  r.num_inliers = Get<int>(j, "num_inliers", where);
  r.time_ms = Get<double>(j, "time_ms", where);
  if (j.contains("objects")) {
    const json& o = j.at("objects");
    const std::string at = where + ".objects";
    r.objects_source = Get<int>(o, "source", at);
    r.objects_target = Get<int>(o, "target", at);
    r.views_source = Get<int>(o, "views_source", at);
    r.views_target = Get<int>(o, "views_target", at);
    r.object_matches = Get<int>(o, "matches", at);
    r.object_matches_correct = Get<int>(o, "correct", at);
    if (o.contains("same_surface")) r.object_matches_same_surface = Get<int>(o, "same_surface", at);
    if (o.contains("matchable")) r.object_pairs_matchable = Get<int>(o, "matchable", at);
    if (o.contains("matchable_same_surface"))
      r.object_pairs_matchable_same_surface = Get<int>(o, "matchable_same_surface", at);
  }
  return r;
}

std::vector<PairRecord> ReadPairsJsonl(const std::string& path, bool* dropped_last_line,
                                       int* superseded) {
  if (dropped_last_line) *dropped_last_line = false;
  if (superseded) *superseded = 0;
  std::ifstream in(path);
  if (!in) return {};
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  std::vector<PairRecord> records;
  std::map<std::string, size_t> index;
  for (size_t n = 0; n < lines.size(); ++n) {
    const std::string where = path + " line " + std::to_string(n + 1);
    const json j = json::parse(lines[n], nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) {
      // Only the last line can be cut short by a killed run; anything else is corruption.
      if (n + 1 == lines.size()) {
        if (dropped_last_line) *dropped_last_line = true;
        break;
      }
      throw MakeInputError(where, "is not valid JSON; expected one pair record per line");
    }
    PairRecord r = PairRecordFromJson(j, where);
    const auto it = index.find(r.key);
    if (it == index.end()) {
      index[r.key] = records.size();
      records.push_back(std::move(r));
    } else {
      records[it->second] = std::move(r);
      if (superseded) ++*superseded;
    }
  }
  return records;
}

void WritePairsJsonl(const std::string& path, const std::vector<PairRecord>& records) {
  // Atomic: this also rewrites a file whose last line an interrupted run left truncated, and a
  // second interruption must not lose the lines already there.
  std::string text;
  for (const PairRecord& r : records) text += detail::DumpJson(PairRecordToJson(r)) + "\n";
  detail::WriteFileAtomically(path, text);
}

}  // namespace zeroreg
