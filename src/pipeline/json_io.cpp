#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "io/text_parsing.hpp"
#include "object_match/graph_match.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/version.hpp"

namespace zeroreg {
namespace {

using nlohmann::json;

// The values a numeric config field accepts: [min, max], the lower end excluded when min_open.
// Integers are also bounded by their C++ type (no silent wrap-around).
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;

  bool Contains(double x) const {
    return x >= min && x <= max && !(min_open && x == min) && !(max_open && x == max);
  }
};
constexpr double kInf = std::numeric_limits<double>::infinity();
Range AtLeast(double min) { return {min, kInf, false, false}; }
Range Positive() { return {0, kInf, true, false}; }
Range Between(double min, double max, bool min_open = false) { return {min, max, min_open, false}; }
Range Open(double min, double max) { return {min, max, true, true}; }
Range Fraction() { return {0, 1, false, false}; }
// Iteration and search counts are bounded, so that every accepted setting finishes (an int's
// 2147483647 Sinkhorn iterations would run for days): 20x to 500x the default
// (docs/FORMATS.md, "Limits").
Range Iterations(double min, double max) { return Between(min, max); }

std::string FormatNumber(double x) {
  // Whole numbers in full (2147483647, not 2.14748e+09), others with enough digits.
  if (x == std::floor(x) && std::abs(x) < 1e18) return std::to_string(static_cast<long long>(x));
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

// "a number > 0", "an integer in [1, 2147483647]", ... for messages.
std::string Describe(const Range& r, bool integer) {
  const std::string kind = integer ? "an integer" : "a number";
  const bool has_min = std::isfinite(r.min), has_max = std::isfinite(r.max);
  if (has_min && has_max) {
    return kind + " in " + (r.min_open ? "(" : "[") + FormatNumber(r.min) + ", " +
           FormatNumber(r.max) + (r.max_open ? ")" : "]");
  }
  if (has_min) return kind + (r.min_open ? " > " : " >= ") + FormatNumber(r.min);
  return integer ? kind : "a finite number";
}

// Every config field is listed once, here, with the range of values it accepts; the JSON writer
// and reader both walk these lists, so the two can never disagree. Keys are the struct field names
// (docs/CONFIG.md). Doubles must also be finite (NaN or infinity is never a usable setting).
template <typename V>
void Visit(V& v, FeatureConfig& c) {
  v("backend", c.backend);
  // Matching holds an n x m similarity of floats: 16384 keypoints a side are 1 GiB.
  v("max_keypoints", c.max_keypoints, Iterations(1, 16384));
  v("xfeat_detection_threshold", c.xfeat_detection_threshold, Fraction());
  v("sift_contrast_threshold", c.sift_contrast_threshold, AtLeast(0));
}
template <typename V>
void Visit(V& v, SinkhornConfig& c) {
  v("iterations", c.iterations, Iterations(1, 1000));
  v("temperature", c.temperature, Positive());
  v("dustbin_score", c.dustbin_score);
  v("min_probability", c.min_probability, Fraction());
  v("mutual", c.mutual);
}
template <typename V>
void Visit(V& v, MatchConfig& c) {
  v("method", c.method);
  v("min_cosine", c.min_cosine, Between(-1, 1));
  v.Section("sinkhorn", c.sinkhorn);
}
template <typename V>
void Visit(V& v, DepthModel& c) {
  v("min_m", c.min_m, AtLeast(0));
  v("max_m", c.max_m, Positive());
  v("edge_relative", c.edge_relative, Positive());
  v("noise_at_1m_m", c.noise_at_1m_m, AtLeast(0));
  v("noise_exponent", c.noise_exponent, AtLeast(0));
}
template <typename V>
void Visit(V& v, LiftConfig& c) {
  v("depth_edge_radius_px", c.depth_edge_radius_px, AtLeast(0));
  v("edge_noise_sigmas", c.edge_noise_sigmas, AtLeast(0));
}
template <typename V>
void Visit(V& v, RansacConfig& c) {
  v("inlier_threshold_m", c.inlier_threshold_m, Positive());
  v("max_iterations", c.max_iterations, Iterations(1, 10000000));
  v("confidence", c.confidence, Open(0, 1));
  v("min_inliers", c.min_inliers, AtLeast(3));  // a rigid transform needs 3 points
  v("min_inlier_ratio", c.min_inlier_ratio, Fraction());
  v("min_inlier_spread_m", c.min_inlier_spread_m, AtLeast(0));
  v("estimator", c.estimator);
  // The graph holds n^2 / 8 bytes: 20000 correspondences are 50 MB.
  v("clique_max_correspondences", c.clique_max_correspondences, Iterations(3, 20000));
  v("clique_noise_bound_m", c.clique_noise_bound_m, AtLeast(0));
  v("clique_max_search_nodes", c.clique_max_search_nodes, Iterations(1, 1000000));
}
template <typename V>
void Visit(V& v, VerifyConfig& c) {
  v("enabled", c.enabled);
  v("pixel_stride", c.pixel_stride, AtLeast(0));
  v("registration_tolerance_m", c.registration_tolerance_m, Positive());
  v("depth_noise_sigmas", c.depth_noise_sigmas, AtLeast(0));
  v("neighbourhood_px", c.neighbourhood_px, AtLeast(0));
  v("min_overlap", c.min_overlap, Fraction());
  v("max_violation", c.max_violation, Fraction());
  v("probe_translation_m", c.probe_translation_m, AtLeast(0));
  v("min_probe_contradicted", c.min_probe_contradicted, Fraction());
  v("min_points", c.min_points, AtLeast(1));
}
template <typename V>
void Visit(V& v, RefineConfig& c) {
  v("enabled", c.enabled);
  v("pixel_stride", c.pixel_stride, AtLeast(0));
  v("voxel_coarse_m", c.voxel_coarse_m, Positive());
  v("max_distance_coarse_m", c.max_distance_coarse_m, Positive());
  v("coarse_iterations", c.coarse_iterations, Iterations(0, 1000));
  v("voxel_m", c.voxel_m, Positive());
  v("max_distance_m", c.max_distance_m, Positive());
  v("max_distance_final_m", c.max_distance_final_m, Positive());
  v("anchor_weight_coarse", c.anchor_weight_coarse, AtLeast(0));
  v("anchor_weight_fine", c.anchor_weight_fine, AtLeast(0));
  v("min_kept_inlier_fraction", c.min_kept_inlier_fraction, Fraction());
  v("max_iterations", c.max_iterations, Iterations(0, 1000));
}
template <typename V>
void Visit(V& v, DetectorConfig& c) {
  v("backend", c.backend);
  v("score_threshold", c.score_threshold, Fraction());
  v("nms_iou", c.nms_iou, Between(0, 1, /*min_open=*/true));
  v("ensemble_below", c.ensemble_below, AtLeast(0));
  v("detections_dir", c.detections_dir);
  v("max_detections", c.max_detections, AtLeast(0));
}
template <typename V>
void Visit(V& v, SegmenterConfig& c) {
  v("backend", c.backend);
  v("grabcut_iterations", c.grabcut_iterations, Iterations(1, 50));
  v("working_size_px", c.working_size_px, AtLeast(8));
  v("crop_margin_fraction", c.crop_margin_fraction, AtLeast(0));
  v("depth_band_min_m", c.depth_band_min_m, AtLeast(0));
  v("depth_band_relative", c.depth_band_relative, AtLeast(0));
  v("depth_band_size_factor", c.depth_band_size_factor, AtLeast(0));
  v("focal_length_fraction", c.focal_length_fraction, Positive());
  v("depth_edge_radius_px", c.depth_edge_radius_px, AtLeast(0));
  v("min_hole_width_px", c.min_hole_width_px, AtLeast(1));
  v("depth_noise_sigmas", c.depth_noise_sigmas, AtLeast(0));
  v("erosion_px", c.erosion_px, AtLeast(0));
  v("min_box_fraction", c.min_box_fraction, Fraction());
  v("sam_min_predicted_iou", c.sam_min_predicted_iou, Fraction());
  v("masks_dir", c.masks_dir);
}
template <typename V>
void Visit(V& v, InferenceConfig& c) {
  v("engine", c.engine);
  v("threads", c.threads, Between(1, 256));
  v("graph_cache", c.graph_cache);
}
template <typename V>
void Visit(V& v, SemanticsConfig& c) {
  v("backend", c.backend);
}
template <typename V>
void Visit(V& v, ObjectsConfig& c) {
  v("min_views", c.min_views, AtLeast(1));
  v("pixel_stride", c.pixel_stride, AtLeast(0));
  v("min_points", c.min_points, AtLeast(1));
  v("association_min_overlap", c.association_min_overlap, Fraction());
  v("association_voxel_m", c.association_voxel_m, Positive());
  v("compatible_label_cosine", c.compatible_label_cosine, Between(-1, 1));
  v("point_voxel_m", c.point_voxel_m, Positive());
  v("association_min_appearance", c.association_min_appearance, Between(-1, 1));
  v("proposals_below", c.proposals_below, AtLeast(0));
  v("appearance", c.appearance);
}
template <typename V>
void Visit(V& v, SceneGraphConfig& c) {
  v("knn", c.knn, AtLeast(1));
  v("symmetric", c.symmetric);
}
template <typename V>
void Visit(V& v, ObjectMatchConfig& c) {
  v("solver", c.solver);
  v("node_weight", c.node_weight, AtLeast(0));
  v("match_cost", c.match_cost);
  v("target_edge_weight", c.target_edge_weight, AtLeast(0));
  v("appearance_weight", c.appearance_weight, AtLeast(0));
  v("max_exact_assignments", c.max_exact_assignments);
  v("min_point_support", c.min_point_support, AtLeast(0));
  v("motion_agreement", c.motion_agreement);
  v("complete_by_motion", c.complete_by_motion);
  v("agree_with_result", c.agree_with_result);
  v("restarts", c.restarts, Iterations(1, 100));
  v("iterations", c.iterations, Iterations(1, 1000));
}
template <typename V>
void Visit(V& v, MethodConfig& c) {
  v("object_level", c.object_level);
  v("detection", c.detection);
  v("point_level", c.point_level);
  v("object_centroid_threshold_m", c.object_centroid_threshold_m, Positive());
  v("scene_graph", c.scene_graph);
  v("clip", c.clip);
  v("min_object_matches", c.min_object_matches, AtLeast(0));
  v("min_object_correspondences", c.min_object_correspondences, AtLeast(0));
  v("whole_image_all_view_pairs", c.whole_image_all_view_pairs);
  v("whole_image_max_view_pairs", c.whole_image_max_view_pairs, AtLeast(-1));
  v("object_all_view_pairs", c.object_all_view_pairs);
}
template <typename V>
void Visit(V& v, HypothesesConfig& c) {
  v("enabled", c.enabled);
  v("always", c.always);
  v("image", c.image);
  v("geometry", c.geometry);
  v("objects", c.objects);
  v("turned_images", c.turned_images);
  v("turned_min_matches", c.turned_min_matches, AtLeast(0));
  v("view_synthesis", c.view_synthesis);
  v("synthesis_max_cameras", c.synthesis_max_cameras, AtLeast(1));
  v("synthesis_orbits", c.synthesis_orbits);
  v("synthesis_min_covered", c.synthesis_min_covered, Fraction());
  v("estimator", c.estimator);
  v("min_inlier_ratio", c.min_inlier_ratio, Fraction());
  v("geometry_voxel_m", c.geometry_voxel_m, Positive());
  v("geometry_pixel_stride", c.geometry_pixel_stride, AtLeast(0));
  v("refuse_degenerate", c.refuse_degenerate);
  v("refine_keeps_evidence", c.refine_keeps_evidence);
  v("min_brightness_rank_correlation", c.min_brightness_rank_correlation, Between(-1, 1));
  v("image_rival", c.image_rival);
  v("image_rival_degenerate", c.image_rival_degenerate);
  v("image_rival_rescued", c.image_rival_rescued);
  v("image_rival_single", c.image_rival_single);
}
template <typename V>
void Visit(V& v, AmbiguityConfig& c) {
  v("enabled", c.enabled);
  v("decisive_inliers", c.decisive_inliers, AtLeast(0));
  v("max_violation", c.max_violation, Fraction());
  v("min_score_fraction", c.min_score_fraction, Fraction());
}
template <typename V>
void Visit(V& v, ScaleConfig& c) {
  v("automatic", c.automatic);
  v("room_min_m", c.room_min_m, Positive());
  v("room_max_m", c.room_max_m, Positive());
  v("working_distance_m", c.working_distance_m, AtLeast(0));
}
template <typename V>
void Visit(V& v, PipelineConfig& c) {
  v.Section("depth", c.depth);
  v.Section("method", c.method);
  v.Section("features", c.features);
  v.Section("match", c.match);
  v.Section("lift", c.lift);
  v.Section("detector", c.detector);
  v.Section("segmenter", c.segmenter);
  v.Section("semantics", c.semantics);
  v.Section("inference", c.inference);
  v.Section("objects", c.objects);
  v.Section("scene_graph", c.scene_graph);
  v.Section("object_match", c.object_match);
  v.Section("ransac", c.ransac);
  v.Section("refine", c.refine);
  v.Section("verify", c.verify);
  v.Section("hypotheses", c.hypotheses);
  v.Section("ambiguity", c.ambiguity);
  v.Section("scale", c.scale);
  v("seed", c.seed);
  v("assets_dir", c.assets_dir);
  v("threads", c.threads, Between(1, 64));
}

class JsonWriter {
 public:
  explicit JsonWriter(json* out) : out_(out) {}
  template <typename T>
  void operator()(const char* key, T& value, Range = {}) {
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

// Settings that were removed, each with what took its place: a config file written for an older
// zeroreg is refused with this instead of the list of known keys. Each brought back a behaviour
// the default had replaced (docs/CONFIG.md, "Removed settings"), or was a second seed the
// pipeline overwrote with `seed`.
constexpr const char* kMovedToDepthRange =
    "moved: every stage reads one depth range, depth.min_m and depth.max_m";
constexpr const char* kMovedToDepthEdge =
    "moved: every stage reads one depth-edge rule, depth.edge_relative";
constexpr const char* kMovedToDepthNoise =
    "moved: the check and ICP read one noise model, depth.noise_at_1m_m and "
    "depth.noise_exponent";
const char* RemovedKey(const std::string& key) {
  static const std::map<std::string, const char*> kRemoved = {
      {"features.xfeat_keep_aspect",
       "was removed: XFeat always scales the image keeping its aspect ratio"},
      {"features.xfeat_square_input",
       "was removed: XFeat runs at the image's own size (the 640x640 square only on "
       "inference.engine \"opencv\")"},
      {"features.xfeat_square_contrast",
       "was removed: XFeat always gets the contrast of the 640x640 square"},
      {"lift.holes_are_edges", "was removed: missing depth is never a keypoint's depth edge"},
      {"refine.anchor_inverse_variance",
       "was removed: the anchors keep their fixed share (refine.anchor_weight_coarse, "
       "refine.anchor_weight_fine)"},
      {"refine.before_fallback",
       "was removed: every candidate is refined by ICP before the arbiter compares them"},
      {"method.label_mask_in_solve", "was removed: the label mask is always part of the solve"},
      {"object_match.rigidity_tolerance_m",
       "was removed: object_match.motion_agreement does its work"},
      {"object_match.seed",
       "was removed: use the top-level \"seed\", which every random step reads"},
      {"segmenter.seed", "was removed: use the top-level \"seed\", which every random step reads"},
      // One depth model for every stage (DepthModel), where each stage had its own copy.
      {"lift.min_depth_m", kMovedToDepthRange},
      {"lift.max_depth_m", kMovedToDepthRange},
      {"verify.min_depth_m", kMovedToDepthRange},
      {"verify.max_depth_m", kMovedToDepthRange},
      {"lift.depth_edge_relative", kMovedToDepthEdge},
      {"segmenter.depth_edge_relative", kMovedToDepthEdge},
      {"verify.depth_edge_relative", kMovedToDepthEdge},
      {"verify.depth_noise_at_1m_m", kMovedToDepthNoise},
      {"refine.depth_noise_at_1m_m", kMovedToDepthNoise},
      {"refine.depth_noise_exponent", kMovedToDepthNoise},
  };
  const auto it = kRemoved.find(key);
  return it == kRemoved.end() ? nullptr : it->second;
}

// Reads the keys present in a JSON object into the fields, checking each value's type and range;
// keys no field claims are an error. Messages read "<source>: <key path> ...", e.g.
// "my.json: ransac.max_iterations is 0; expected an integer in [1, 2147483647]".
class JsonReader {
 public:
  JsonReader(const json& in, std::string source, std::string prefix)
      : in_(in), source_(std::move(source)), prefix_(std::move(prefix)) {
    if (!in_.is_object()) {
      throw MakeInputError(source_, (prefix_.empty() ? std::string("the config") : prefix_) +
                                        " must be a JSON object, got " + Shown(in_));
    }
  }
  void operator()(const char* key, std::string& value) {
    if (const json* j = Claim(key)) {
      if (!j->is_string()) Fail(key, "is " + Shown(*j) + "; expected a string");
      value = j->get<std::string>();
    }
  }
  void operator()(const char* key, bool& value) {
    if (const json* j = Claim(key)) {
      if (!j->is_boolean()) Fail(key, "is " + Shown(*j) + "; expected true or false");
      value = j->get<bool>();
    }
  }
  void operator()(const char* key, double& value, Range range = {}) {
    if (const json* j = Claim(key)) {
      const double x = j->is_number() ? j->get<double>() : std::nan("");
      if (!j->is_number() || !std::isfinite(x) || !range.Contains(x)) {
        Fail(key, "is " + Shown(*j) + "; expected " + Describe(range, false));
      }
      value = x;
    }
  }
  void operator()(const char* key, int& value, Range range = {}) {
    value = static_cast<int>(ReadInteger(key, value, range, std::numeric_limits<int>::max()));
  }
  void operator()(const char* key, std::uint64_t& value) {
    if (const json* j = Claim(key)) {
      // nlohmann stores every non-negative integer literal parsed from text as unsigned; one
      // built in code (the Python module's int64) may be signed and still non-negative.
      const bool non_negative_integer =
          j->is_number_unsigned() || (j->is_number_integer() && j->get<std::int64_t>() >= 0);
      if (!non_negative_integer) {
        Fail(key, "is " + Shown(*j) + "; expected an integer in [0, 18446744073709551615]");
      }
      value = j->get<std::uint64_t>();
    }
  }
  void operator()(const char* key, ObjectMatchSolver& value) {
    std::string name = ToString(value);
    (*this)(key, name);
    try {
      value = ObjectMatchSolverFromString(name);
    } catch (const std::exception& e) {
      Fail(key, e.what());
    }
  }
  template <typename S>
  void Section(const char* key, S& section) {
    if (const json* j = Claim(key)) {
      JsonReader reader(*j, source_, Path(key));
      Visit(reader, section);
      reader.Finish();
    }
  }
  void Finish() const {
    for (auto it = in_.begin(); it != in_.end(); ++it) {
      if (!claimed_.count(it.key())) {
        if (const char* removed = RemovedKey(Path(it.key()))) {
          throw MakeInputError(source_, Path(it.key()) + " " + removed);
        }
        std::string known;
        for (const std::string& k : claimed_) known += (known.empty() ? "" : ", ") + k;
        throw MakeInputError(source_, "unknown key '" + Path(it.key()) + "'; known keys" +
                                          (prefix_.empty() ? "" : " of " + prefix_) + ": " + known);
      }
    }
  }

 private:
  const json* Claim(const char* key) {
    claimed_.insert(key);
    auto it = in_.find(key);
    return it == in_.end() ? nullptr : &*it;
  }
  std::string Path(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }
  // The value as written in JSON; a string is quoted, so 1e999 given as text shows as "1e999".
  static std::string Shown(const json& j) {
    if (j.is_number_float() && !std::isfinite(j.get<double>())) {  // dump() would say null
      const double x = j.get<double>();
      return std::isnan(x) ? "NaN" : (x > 0 ? "inf" : "-inf");
    }
    return detail::DumpJson(j);
  }
  [[noreturn]] void Fail(const std::string& key, const std::string& problem) const {
    throw MakeInputError(source_, Path(key) + " " + problem);
  }
  // An integer value within `range` and [0 or INT_MIN, type_max]; floats and booleans are refused.
  long long ReadInteger(const char* key, long long current, Range range, long long type_max) {
    const json* j = Claim(key);
    if (j == nullptr) return current;
    range.max = std::min(range.max, static_cast<double>(type_max));
    range.min = std::max(range.min, -static_cast<double>(type_max) - 1);
    const bool integer = j->is_number_integer();
    // Compare as unsigned first, so that 4294967297 or 2^63 cannot wrap into range.
    const bool too_big =
        j->is_number_unsigned() && j->get<std::uint64_t>() > static_cast<std::uint64_t>(type_max);
    const long long x = integer && !too_big ? j->get<long long>() : 0;
    if (!integer || too_big || !range.Contains(static_cast<double>(x))) {
      Fail(key, "is " + Shown(*j) + "; expected " + Describe(range, true));
    }
    return x;
  }

  const json& in_;
  std::string source_, prefix_;
  std::set<std::string> claimed_;
};

// Checks between fields (each field's own range is checked as it is read).
void CheckRelations(const PipelineConfig& c, const std::string& where) {
  for (const auto& [key, name] :
       {std::pair<const char*, const std::string&>{"ransac.estimator", c.ransac.estimator},
        {"hypotheses.estimator", c.hypotheses.estimator}}) {
    if (name != "ransac" && name != "clique") {
      throw MakeInputError(
          where, std::string(key) + " is \"" + name + "\"; expected \"ransac\" or \"clique\"");
    }
  }
  if (c.objects.appearance != "auto" && c.objects.appearance != "colour" &&
      c.objects.appearance != "sam-embedding") {
    throw MakeInputError(where, "objects.appearance is \"" + c.objects.appearance +
                                    "\"; expected \"auto\", \"colour\" or \"sam-embedding\"");
  }
  if (c.objects.appearance == "sam-embedding" && c.segmenter.backend != "sam") {
    throw MakeInputError(where,
                         "objects.appearance \"sam-embedding\" needs segmenter.backend "
                         "\"sam\" (it pools SAM's image embedding), but the segmenter is "
                         "\"" +
                             c.segmenter.backend + "\"");
  }
  if (!(c.scale.room_min_m <= c.scale.room_max_m)) {
    throw MakeInputError(where, "scale.room_min_m (" + FormatNumber(c.scale.room_min_m) +
                                    ") must not exceed scale.room_max_m (" +
                                    FormatNumber(c.scale.room_max_m) + ")");
  }
  if (!(c.depth.min_m < c.depth.max_m)) {
    throw MakeInputError(where, "depth.min_m (" + FormatNumber(c.depth.min_m) +
                                    ") must be below depth.max_m (" + FormatNumber(c.depth.max_m) +
                                    ")");
  }
}

}  // namespace

json ConfigToJson(const PipelineConfig& config) {
  PipelineConfig copy = config;
  json out = json::object();
  JsonWriter writer(&out);
  Visit(writer, copy);
  return out;
}

void ApplyConfigJson(const json& j, const std::string& where, PipelineConfig* c) {
  JsonReader reader(j, where, "");
  Visit(reader, *c);
  reader.Finish();
  CheckRelations(*c, where);
}

void ValidateConfig(const PipelineConfig& config, const std::string& where) {
  // The JSON form holds every field, so reading it back applies every type and range check.
  PipelineConfig copy;
  ApplyConfigJson(ConfigToJson(config), where, &copy);
}

PipelineConfig ReadConfigFile(const std::string& path) {
  const json j = detail::ReadJsonFile(path, "config file");
  PipelineConfig config;
  ApplyConfigJson(j, path, &config);
  return config;
}

namespace {

// The value of a --set assignment: JSON when it parses (numbers, true, [..]), else the bare word
// as a string (features.backend=sift). A number JSON cannot hold (1e999) is an error, not a word.
json ParseOverrideValue(const std::string& text, const std::string& where) {
  try {
    return json::parse(text);
  } catch (const json::out_of_range&) {
    throw MakeInputError(where, "'" + text + "' is out of the range of a double");
  } catch (const json::exception&) {
    return text;
  }
}

}  // namespace

void ApplyConfigOverride(const std::string& assignment, PipelineConfig* config) {
  const std::string where = "--set " + assignment;
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw MakeInputError(where, "expected section.key=value, e.g. ransac.inlier_threshold_m=0.03");
  }
  const std::string key = assignment.substr(0, eq);
  json patch = ParseOverrideValue(assignment.substr(eq + 1), where);
  // Build {"a": {"b": value}} from "a.b".
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  for (auto it = parts.rbegin(); it != parts.rend(); ++it) patch = json{{*it, patch}};
  ApplyConfigJson(patch, where, config);
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
         {"outside_prior", r.outside_prior},
         {"reason", r.reason},
         {"path", PathName(r.path)},
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
  // The refusal as data (null for a valid result); `reason` stays the prose.
  j["refusal"] = nullptr;
  if (r.refusal.test != RefusalTest::kNone) {
    j["refusal"] = {{"test", RefusalTestName(r.refusal.test)},
                    {"measured", r.refusal.measured},
                    {"threshold", r.refusal.threshold}};
  }
  if (r.verification.ran) {
    const VerificationResult& v = r.verification;
    j["verification"] = {
        {"passed", v.passed},
        {"reason", v.reason},
        {"overlap", v.overlap},
        {"overlap_max", v.overlap_max},
        {"violation", v.violation},
        {"residual_rms_m", v.residual_rms_m},
        {"score", v.score},
        {"probe_contradicted", v.probe_contradicted},
        {"degenerate", v.degenerate},
        {"brightness_rank_correlation", std::isfinite(v.brightness_rank_correlation)
                                            ? json(v.brightness_rank_correlation)
                                            : json(nullptr)},
        {"source_samples", v.source_samples},
        {"target_samples", v.target_samples}};
    json candidates = json::array();
    for (const CandidateSummary& c : r.candidates) {
      candidates.push_back({{"name", c.name},
                            {"T_target_source", TransformToJson(c.T_target_source)},
                            {"score", c.score},
                            {"passed", c.passed},
                            {"chosen", c.chosen},
                            {"outside_prior", c.outside_prior}});
    }
    j["candidates"] = candidates;
  }
  // Every pose that fits an ambiguous pair (or that a motion prior ruled out), the reported first.
  j["ambiguous"] = r.ambiguous;
  json alternatives = json::array();
  for (const Alternative& a : r.alternatives) {
    const double rho = a.brightness_rank_correlation;
    alternatives.push_back(
        {{"name", a.name},
         {"T_target_source", TransformToJson(a.T_target_source)},
         {"score", a.score},
         {"overlap", a.overlap},
         {"violation", a.violation},
         {"brightness_rank_correlation", std::isfinite(rho) ? json(rho) : json()},
         {"inliers", a.num_inliers},
         {"apart_m", a.apart_m},
         {"outside_prior", a.outside_prior}});
  }
  j["alternatives"] = alternatives;
  if (r.rendered_view) {
    const RenderedCamera& c = *r.rendered_view;
    j["rendered_view"] = {{"source_view", c.source_view},
                          {"T_target_camera", TransformToJson(c.T_target_camera)},
                          {"from", c.from}};
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
      if (m.point_support >= 0) matches.back()["point_support"] = m.point_support;
    }
    j["objects"] = {{"source", ObjectsToJson(r.source_objects)},
                    {"target", ObjectsToJson(r.target_objects)},
                    {"matches", matches},
                    {"rejected_matches", r.rejected_object_matches}};
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
