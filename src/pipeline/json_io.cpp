#include <fstream>
#include <set>

#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;

// Reads the fields of one config section. Each Field call consumes a key; Finish() reports any
// key that no field consumed.
class SectionReader {
 public:
  SectionReader(const json& section, std::string where)
      : section_(section), where_(std::move(where)) {
    if (!section_.is_object()) throw MakeInputError(where_, "expected a JSON object");
  }
  template <typename T>
  SectionReader& Field(const char* key, T* value) {
    seen_.insert(key);
    auto it = section_.find(key);
    if (it == section_.end()) return *this;
    try {
      *value = it->get<T>();
    } catch (const json::exception& e) {
      throw MakeInputError(where_ + "." + key, std::string("wrong value type (") + e.what() + ")");
    }
    return *this;
  }
  const json* Section(const char* key) {
    seen_.insert(key);
    auto it = section_.find(key);
    return it == section_.end() ? nullptr : &*it;
  }
  void Finish() const {
    for (auto it = section_.begin(); it != section_.end(); ++it) {
      if (!seen_.count(it.key())) {
        std::string known;
        for (const std::string& k : seen_) known += (known.empty() ? "" : ", ") + k;
        throw MakeInputError(where_, "unknown key '" + it.key() + "'; known keys: " + known);
      }
    }
  }

 private:
  const json& section_;
  std::string where_;
  std::set<std::string> seen_;
};

}  // namespace

json ConfigToJson(const PipelineConfig& c) {
  return json{
      {"features",
       {{"backend", c.features.backend},
        {"max_keypoints", c.features.max_keypoints},
        {"xfeat_detection_threshold", c.features.xfeat_detection_threshold},
        {"sift_contrast_threshold", c.features.sift_contrast_threshold}}},
      {"match", {{"method", c.match.method}, {"min_cosine", c.match.min_cosine}}},
      {"lift",
       {{"min_depth_m", c.lift.min_depth_m},
        {"max_depth_m", c.lift.max_depth_m},
        {"depth_edge_radius_px", c.lift.depth_edge_radius_px},
        {"depth_edge_relative", c.lift.depth_edge_relative}}},
      {"ransac",
       {{"inlier_threshold_m", c.ransac.inlier_threshold_m},
        {"max_iterations", c.ransac.max_iterations},
        {"confidence", c.ransac.confidence},
        {"min_inliers", c.ransac.min_inliers},
        {"min_inlier_ratio", c.ransac.min_inlier_ratio}}},
      {"seed", c.seed},
      {"assets_dir", c.assets_dir},
  };
}

void ApplyConfigJson(const json& j, const std::string& where, PipelineConfig* c) {
  SectionReader root(j, where);
  if (const json* s = root.Section("features")) {
    SectionReader(*s, where + ": features")
        .Field("backend", &c->features.backend)
        .Field("max_keypoints", &c->features.max_keypoints)
        .Field("xfeat_detection_threshold", &c->features.xfeat_detection_threshold)
        .Field("sift_contrast_threshold", &c->features.sift_contrast_threshold)
        .Finish();
  }
  if (const json* s = root.Section("match")) {
    SectionReader(*s, where + ": match")
        .Field("method", &c->match.method)
        .Field("min_cosine", &c->match.min_cosine)
        .Finish();
  }
  if (const json* s = root.Section("lift")) {
    SectionReader(*s, where + ": lift")
        .Field("min_depth_m", &c->lift.min_depth_m)
        .Field("max_depth_m", &c->lift.max_depth_m)
        .Field("depth_edge_radius_px", &c->lift.depth_edge_radius_px)
        .Field("depth_edge_relative", &c->lift.depth_edge_relative)
        .Finish();
  }
  if (const json* s = root.Section("ransac")) {
    SectionReader(*s, where + ": ransac")
        .Field("inlier_threshold_m", &c->ransac.inlier_threshold_m)
        .Field("max_iterations", &c->ransac.max_iterations)
        .Field("confidence", &c->ransac.confidence)
        .Field("min_inliers", &c->ransac.min_inliers)
        .Field("min_inlier_ratio", &c->ransac.min_inlier_ratio)
        .Finish();
  }
  root.Field("seed", &c->seed).Field("assets_dir", &c->assets_dir).Finish();
  if (c->features.max_keypoints <= 0) {
    throw MakeInputError(where + ": features.max_keypoints", "must be positive");
  }
  if (!(c->ransac.inlier_threshold_m > 0)) {
    throw MakeInputError(where + ": ransac.inlier_threshold_m", "must be positive (metres)");
  }
  if (!(c->ransac.confidence > 0 && c->ransac.confidence < 1)) {
    throw MakeInputError(where + ": ransac.confidence", "must be in (0, 1)");
  }
}

PipelineConfig ReadConfigFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MakeInputError(path, "cannot open the config file");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw MakeInputError(path, std::string("not valid JSON (") + e.what() + ")");
  }
  PipelineConfig config;
  ApplyConfigJson(j, path, &config);
  return config;
}

void ApplyConfigOverride(const std::string& assignment, PipelineConfig* config) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw MakeInputError("--set " + assignment, "expected section.key=value, e.g. ransac.seed=1");
  }
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  json value;
  try {
    value = json::parse(text);
  } catch (const json::exception&) {
    value = text;  // bare words are strings: features.backend=sift
  }
  json patch = value;
  // Build {"a": {"b": value}} from "a.b".
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) patch = json{{*it, patch}};
  ApplyConfigJson(patch, "--set " + assignment, config);
}

json TransformToJson(const Transform& T) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({T(r, 0), T(r, 1), T(r, 2), T(r, 3)});
  return rows;
}

json ResultToJson(const RegistrationResult& r, bool include_correspondences) {
  json timings = json::object();
  for (const StageTime& t : r.timings) timings[t.stage] = t.ms;
  json j{{"T_target_source", TransformToJson(r.T_target_source)},
         {"valid", r.valid},
         {"reason", r.reason},
         {"path", r.path},
         {"counts",
          {{"keypoints_source", r.num_keypoints_source},
           {"keypoints_target", r.num_keypoints_target},
           {"correspondences", r.num_correspondences},
           {"inliers", r.num_inliers},
           {"ransac_iterations", r.ransac_iterations}}},
         {"inlier_ratio", r.inlier_ratio},
         {"inlier_rmse_m", r.inlier_rmse},
         {"timings_ms", timings}};
  if (include_correspondences) {
    json list = json::array();
    for (size_t i = 0; i < r.correspondences.size(); ++i) {
      const Correspondence& c = r.correspondences[i];
      list.push_back({{"source", {c.source.x(), c.source.y(), c.source.z()}},
                      {"target", {c.target.x(), c.target.y(), c.target.z()}},
                      {"source_pixel", {c.source_pixel.x(), c.source_pixel.y()}},
                      {"target_pixel", {c.target_pixel.x(), c.target_pixel.y()}},
                      {"view", c.view},
                      {"score", c.score},
                      {"inlier", i < r.is_inlier.size() && r.is_inlier[i]}});
    }
    j["correspondences"] = list;
  }
  return j;
}

}  // namespace zeroreg
