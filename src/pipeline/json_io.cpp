#include <fstream>
#include <set>

#include "object_match/graph_match.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;

// Every config field is listed once, here; the JSON writer and reader both walk these lists, so
// the two can never disagree. Keys are the struct field names (docs/CONFIG.md).
template <typename V>
void Visit(V& v, FeatureConfig& c) {
  v("backend", c.backend);
  v("max_keypoints", c.max_keypoints);
  v("xfeat_detection_threshold", c.xfeat_detection_threshold);
  v("xfeat_keep_aspect", c.xfeat_keep_aspect);
  v("sift_contrast_threshold", c.sift_contrast_threshold);
}
template <typename V>
void Visit(V& v, SinkhornConfig& c) {
  v("iterations", c.iterations);
  v("temperature", c.temperature);
  v("dustbin_score", c.dustbin_score);
  v("min_probability", c.min_probability);
  v("mutual", c.mutual);
}
template <typename V>
void Visit(V& v, MatchConfig& c) {
  v("method", c.method);
  v("min_cosine", c.min_cosine);
  v.Section("sinkhorn", c.sinkhorn);
}
template <typename V>
void Visit(V& v, LiftConfig& c) {
  v("min_depth_m", c.min_depth_m);
  v("max_depth_m", c.max_depth_m);
  v("depth_edge_radius_px", c.depth_edge_radius_px);
  v("depth_edge_relative", c.depth_edge_relative);
  v("holes_are_edges", c.holes_are_edges);
}
template <typename V>
void Visit(V& v, RansacConfig& c) {
  v("inlier_threshold_m", c.inlier_threshold_m);
  v("max_iterations", c.max_iterations);
  v("confidence", c.confidence);
  v("min_inliers", c.min_inliers);
  v("min_inlier_ratio", c.min_inlier_ratio);
  v("min_inlier_spread_m", c.min_inlier_spread_m);
}
template <typename V>
void Visit(V& v, VerifyConfig& c) {
  v("enabled", c.enabled);
  v("pixel_stride", c.pixel_stride);
  v("min_depth_m", c.min_depth_m);
  v("max_depth_m", c.max_depth_m);
  v("registration_tolerance_m", c.registration_tolerance_m);
  v("depth_noise_at_1m_m", c.depth_noise_at_1m_m);
  v("depth_noise_sigmas", c.depth_noise_sigmas);
  v("neighbourhood_px", c.neighbourhood_px);
  v("depth_edge_relative", c.depth_edge_relative);
  v("min_overlap", c.min_overlap);
  v("max_violation", c.max_violation);
  v("probe_translation_m", c.probe_translation_m);
  v("min_probe_contradicted", c.min_probe_contradicted);
  v("min_points", c.min_points);
}
template <typename V>
void Visit(V& v, RefineConfig& c) {
  v("enabled", c.enabled);
  v("voxel_coarse_m", c.voxel_coarse_m);
  v("max_distance_coarse_m", c.max_distance_coarse_m);
  v("coarse_iterations", c.coarse_iterations);
  v("voxel_m", c.voxel_m);
  v("max_distance_m", c.max_distance_m);
  v("max_distance_final_m", c.max_distance_final_m);
  v("anchor_weight_coarse", c.anchor_weight_coarse);
  v("anchor_weight_fine", c.anchor_weight_fine);
  v("min_kept_inlier_fraction", c.min_kept_inlier_fraction);
  v("max_iterations", c.max_iterations);
}
template <typename V>
void Visit(V& v, DetectorConfig& c) {
  v("backend", c.backend);
  v("score_threshold", c.score_threshold);
  v("nms_iou", c.nms_iou);
  v("detections_dir", c.detections_dir);
}
template <typename V>
void Visit(V& v, SegmenterConfig& c) {
  v("backend", c.backend);
  v("grabcut_iterations", c.grabcut_iterations);
  v("working_size_px", c.working_size_px);
  v("crop_margin_fraction", c.crop_margin_fraction);
  v("depth_band_min_m", c.depth_band_min_m);
  v("depth_band_relative", c.depth_band_relative);
  v("depth_band_size_factor", c.depth_band_size_factor);
  v("focal_length_fraction", c.focal_length_fraction);
  v("depth_edge_radius_px", c.depth_edge_radius_px);
  v("depth_edge_relative", c.depth_edge_relative);
  v("erosion_px", c.erosion_px);
  v("min_box_fraction", c.min_box_fraction);
  v("masks_dir", c.masks_dir);
}
template <typename V>
void Visit(V& v, SemanticsConfig& c) {
  v("backend", c.backend);
}
template <typename V>
void Visit(V& v, ObjectsConfig& c) {
  v("min_views", c.min_views);
  v("pixel_stride", c.pixel_stride);
  v("min_points", c.min_points);
  v("association_min_overlap", c.association_min_overlap);
  v("association_voxel_m", c.association_voxel_m);
  v("compatible_label_cosine", c.compatible_label_cosine);
  v("point_voxel_m", c.point_voxel_m);
}
template <typename V>
void Visit(V& v, SceneGraphConfig& c) {
  v("knn", c.knn);
  v("symmetric", c.symmetric);
}
template <typename V>
void Visit(V& v, ObjectMatchConfig& c) {
  v("solver", c.solver);
  v("node_weight", c.node_weight);
  v("match_cost", c.match_cost);
  v("target_edge_weight", c.target_edge_weight);
  v("max_exact_assignments", c.max_exact_assignments);
  v("restarts", c.restarts);
  v("iterations", c.iterations);
}
template <typename V>
void Visit(V& v, MethodConfig& c) {
  v("object_level", c.object_level);
  v("detection", c.detection);
  v("point_level", c.point_level);
  v("object_centroid_threshold_m", c.object_centroid_threshold_m);
  v("scene_graph", c.scene_graph);
  v("clip", c.clip);
  v("label_mask_in_solve", c.label_mask_in_solve);
  v("min_object_matches", c.min_object_matches);
  v("min_object_correspondences", c.min_object_correspondences);
  v("whole_image_all_view_pairs", c.whole_image_all_view_pairs);
}
template <typename V>
void Visit(V& v, PipelineConfig& c) {
  v.Section("method", c.method);
  v.Section("features", c.features);
  v.Section("match", c.match);
  v.Section("lift", c.lift);
  v.Section("detector", c.detector);
  v.Section("segmenter", c.segmenter);
  v.Section("semantics", c.semantics);
  v.Section("objects", c.objects);
  v.Section("scene_graph", c.scene_graph);
  v.Section("object_match", c.object_match);
  v.Section("ransac", c.ransac);
  v.Section("refine", c.refine);
  v.Section("verify", c.verify);
  v("seed", c.seed);
  v("assets_dir", c.assets_dir);
}

class JsonWriter {
 public:
  explicit JsonWriter(json* out) : out_(out) {}
  template <typename T>
  void operator()(const char* key, T& value) {
    (*out_)[key] = value;
  }
  void operator()(const char* key, ObjectMatchSolver& value) { (*out_)[key] = ToString(value); }
  template <typename S>
  void Section(const char* key, S& section) {
    json child = json::object();
    JsonWriter writer(&child);
    Visit(writer, section);
    (*out_)[key] = child;
  }

 private:
  json* out_;
};

// Reads the keys present in a JSON object into the fields; keys no field claims are an error.
class JsonReader {
 public:
  JsonReader(const json& in, std::string where) : in_(in), where_(std::move(where)) {
    if (!in_.is_object()) throw MakeInputError(where_, "expected a JSON object");
  }
  template <typename T>
  void operator()(const char* key, T& value) {
    if (const json* j = Claim(key)) {
      try {
        value = j->get<T>();
      } catch (const json::exception& e) {
        throw MakeInputError(where_ + "." + key,
                             std::string("wrong value type (") + e.what() + ")");
      }
    }
  }
  void operator()(const char* key, ObjectMatchSolver& value) {
    std::string name = ToString(value);
    (*this)(key, name);
    try {
      value = ObjectMatchSolverFromString(name);
    } catch (const std::exception& e) {
      throw MakeInputError(where_ + "." + key, e.what());
    }
  }
  template <typename S>
  void Section(const char* key, S& section) {
    if (const json* j = Claim(key)) {
      JsonReader reader(*j, where_ + "." + key);
      Visit(reader, section);
      reader.Finish();
    }
  }
  void Finish() const {
    for (auto it = in_.begin(); it != in_.end(); ++it) {
      if (!claimed_.count(it.key())) {
        std::string known;
        for (const std::string& k : claimed_) known += (known.empty() ? "" : ", ") + k;
        throw MakeInputError(where_, "unknown key '" + it.key() + "'; known keys: " + known);
      }
    }
  }

 private:
  const json* Claim(const char* key) {
    claimed_.insert(key);
    auto it = in_.find(key);
    return it == in_.end() ? nullptr : &*it;
  }
  const json& in_;
  std::string where_;
  std::set<std::string> claimed_;
};

}  // namespace

json ConfigToJson(const PipelineConfig& config) {
  PipelineConfig copy = config;
  json out = json::object();
  JsonWriter writer(&out);
  Visit(writer, copy);
  return out;
}

void ApplyConfigJson(const json& j, const std::string& where, PipelineConfig* c) {
  JsonReader reader(j, where);
  Visit(reader, *c);
  reader.Finish();
  if (c->features.max_keypoints <= 0) {
    throw MakeInputError(where + ": features.max_keypoints", "must be positive");
  }
  if (!(c->ransac.inlier_threshold_m > 0)) {
    throw MakeInputError(where + ": ransac.inlier_threshold_m", "must be positive (metres)");
  }
  if (!(c->ransac.confidence > 0 && c->ransac.confidence < 1)) {
    throw MakeInputError(where + ": ransac.confidence", "must be in (0, 1)");
  }
  if (c->scene_graph.knn < 1) throw MakeInputError(where + ": scene_graph.knn", "must be >= 1");
  if (c->verify.pixel_stride < 1) {
    throw MakeInputError(where + ": verify.pixel_stride", "must be >= 1 (pixels)");
  }
  if (!(c->verify.registration_tolerance_m > 0) || !(c->verify.depth_noise_at_1m_m >= 0) ||
      !(c->verify.depth_noise_sigmas >= 0)) {
    throw MakeInputError(where + ": verify",
                         "registration_tolerance_m must be positive and the depth noise terms "
                         "non-negative (metres)");
  }
  if (c->objects.pixel_stride < 1) {
    throw MakeInputError(where + ": objects.pixel_stride", "must be >= 1 (pixels)");
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

namespace {

json ObjectsToJson(const std::vector<ObjectSummary>& objects) {
  json list = json::array();
  for (const ObjectSummary& o : objects) {
    json views = json::array();
    for (const ObjectView& v : o.views) {
      views.push_back({{"view", v.view},
                       {"box_xywh", {v.box.x, v.box.y, v.box.width, v.box.height}},
                       {"score", v.score}});
    }
    list.push_back({{"label", o.label},
                    {"score", o.score},
                    {"centroid", {o.centroid.x(), o.centroid.y(), o.centroid.z()}},
                    {"num_points", o.num_points},
                    {"views", views}});
  }
  return list;
}

}  // namespace

json ResultToJson(const RegistrationResult& r, bool include_correspondences) {
  json timings = json::object();
  for (const StageTime& t : r.timings) timings[t.stage] = t.ms;
  json j{{"zeroreg_version", ZEROREG_VERSION},
         {"T_target_source", TransformToJson(r.T_target_source)},
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
         {"inlier_spread_m", r.inlier_spread_m},
         {"count_test_passed", r.count_test_passed},
         {"timings_ms", timings}};
  if (r.verification.ran) {
    const VerificationResult& v = r.verification;
    j["verification"] = {{"passed", v.passed},
                         {"reason", v.reason},
                         {"overlap", v.overlap},
                         {"overlap_max", v.overlap_max},
                         {"violation", v.violation},
                         {"residual_rms_m", v.residual_rms_m},
                         {"score", v.score},
                         {"probe_contradicted", v.probe_contradicted},
                         {"degenerate", v.degenerate},
                         {"source_samples", v.source_samples},
                         {"target_samples", v.target_samples}};
    json candidates = json::array();
    for (const CandidateSummary& c : r.candidates) {
      candidates.push_back({{"name", c.name},
                            {"T_target_source", TransformToJson(c.T_target_source)},
                            {"score", c.score},
                            {"passed", c.passed},
                            {"chosen", c.chosen}});
    }
    j["candidates"] = candidates;
  }
  if (!r.source_objects.empty() || !r.target_objects.empty()) {
    json matches = json::array();
    for (const ObjectMatchSummary& m : r.object_matches) {
      matches.push_back({{"source", m.source},
                         {"target", m.target},
                         {"source_label", r.source_objects[m.source].label},
                         {"target_label", r.target_objects[m.target].label},
                         {"node_similarity", m.node_similarity},
                         {"correspondences", m.num_correspondences}});
    }
    j["objects"] = {{"source", ObjectsToJson(r.source_objects)},
                    {"target", ObjectsToJson(r.target_objects)},
                    {"matches", matches}};
  }
  if (include_correspondences) {
    json list = json::array();
    for (size_t i = 0; i < r.correspondences.size(); ++i) {
      const Correspondence& c = r.correspondences[i];
      list.push_back({{"source", {c.source.x(), c.source.y(), c.source.z()}},
                      {"target", {c.target.x(), c.target.y(), c.target.z()}},
                      {"source_pixel", {c.source_pixel.x(), c.source_pixel.y()}},
                      {"target_pixel", {c.target_pixel.x(), c.target_pixel.y()}},
                      {"view", c.view},
                      {"target_view", c.target_view},
                      {"score", c.score},
                      {"inlier", i < r.is_inlier.size() && r.is_inlier[i]}});
    }
    j["correspondences"] = list;
  }
  return j;
}

}  // namespace zeroreg
