#include "eval/methods.hpp"

#include <exception>
#include <future>
#include <mutex>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "estimate/lift.hpp"
#include "estimate/rigid_ransac.hpp"
#include "eval/prepared_cache.hpp"
#include "features/fpfh.hpp"
#include "open3d_module/open3d_module.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

// One Pipeline (thread-safe; its models are loaded once) and one cache of prepared scans, shared
// by the instances of every runner thread.
struct SharedPipeline {
  SharedPipeline(const PipelineConfig& config, const PreparedCacheOptions& cache)
      : pipeline(config),
        prepared(cache.max_scans, cache.max_bytes),
        cached(cache.max_scans > 0),
        target_refs(cache.target_refs) {}
  // Whether the scan `ref` is ever a target (true when that is not known).
  bool MayBeTarget(const std::string& ref) const {
    return target_refs.empty() || target_refs.count(ref) > 0;
  }
  Pipeline pipeline;
  PreparedScanCache prepared;
  bool cached;
  std::set<std::string> target_refs;
};

class ZeroregMethod : public PairMethod {
 public:
  ZeroregMethod(std::shared_ptr<SharedPipeline> shared, bool require_image_path)
      : shared_(std::move(shared)), require_image_path_(require_image_path) {}

  MethodOutput Run(const Scan& source, const Scan& target) override {
    return Run(source, target, std::nullopt);
  }

  MethodOutput RunRefs(const std::string& source_ref, const std::string& target_ref,
                       const ScanLoadFunction& load,
                       const std::optional<MotionPrior>& prior) override {
    if (!shared_->cached) return Run(load(source_ref), load(target_ref), prior);
    const auto prepared = [&](const std::string& ref) {
      return shared_->prepared.Get(
          ref, [&] { return shared_->pipeline.Prepare(load(ref), shared_->MayBeTarget(ref)); });
    };
    // Both scans at once when they are both new (as Register(scan, scan) would); a cached one
    // returns at once.
    PreparedScan source, target;
    if (shared_->pipeline.config().threads >= 2) {
      std::future<PreparedScan> pending =
          std::async(std::launch::async, [&] { return prepared(source_ref); });
      std::exception_ptr target_error;
      try {
        target = prepared(target_ref);
      } catch (...) {
        target_error = std::current_exception();
      }
      source = pending.get();  // the source's error first, as in the serial order
      if (target_error) std::rethrow_exception(target_error);
    } else {
      source = prepared(source_ref);
      target = prepared(target_ref);
    }
    return Output(shared_->pipeline.Register(source, target, prior), source.scan().views.size(),
                  target.scan().views.size(), prior.has_value());
  }

 private:
  MethodOutput Run(const Scan& source, const Scan& target,
                   const std::optional<MotionPrior>& prior) {
    return Output(shared_->pipeline.Register(source, target, prior), source.views.size(),
                  target.views.size(), prior.has_value());
  }

  // `with_prior`: the pair was registered with a motion prior, whose own refinement (paths "prior"
  // and "prior icp", tried when no source is valid within it) is part of any method given one.
  MethodOutput Output(RegistrationResult r, size_t views_source, size_t views_target,
                      bool with_prior) const {
    const bool from_prior = with_prior && ComesFromMotionPrior(r);
    if (require_image_path_ && r.path != Path{PathSource::kImage} && !from_prior) {
      // A stale ImagePathOverrides() would silently evaluate the wrong method.
      throw std::logic_error("--method image: the pipeline used the '" + PathName(r.path) +
                             "' path; update ImagePathOverrides() in src/eval/methods.cpp");
    }
    MethodOutput out;
    out.T_target_source = r.T_target_source;
    out.valid = r.valid;
    out.reason = r.reason;
    out.path = PathName(r.path);
    out.correspondences = std::move(r.correspondences);
    out.num_inliers = r.num_inliers;
    for (const ObjectSummary& o : r.source_objects) {
      out.source_object_centroids.push_back(o.centroid);
      out.source_object_labels.push_back(o.label);
    }
    for (const ObjectSummary& o : r.target_objects) {
      out.target_object_centroids.push_back(o.centroid);
      out.target_object_labels.push_back(o.label);
    }
    for (const ObjectMatchSummary& m : r.object_matches)
      out.object_matches.push_back({m.source, m.target});
    // The objects' surfaces, for the surface measure of the matches (moved: `r` is ours).
    for (ObjectSummary& o : r.source_objects)
      out.source_object_surfaces.push_back(std::move(o.points));
    for (ObjectSummary& o : r.target_objects)
      out.target_object_surfaces.push_back(std::move(o.points));
    out.views_source = static_cast<int>(views_source);
    out.views_target = static_cast<int>(views_target);
    return out;
  }

  std::shared_ptr<SharedPipeline> shared_;
  bool require_image_path_;
};

class FpfhMethod : public PairMethod {
 public:
  explicit FpfhMethod(const FpfhConfig& config) : c_(config) {}

  MethodOutput Run(const Scan& source, const Scan& target) override {
    const FpfhCloud src = Prepare(source);
    const FpfhCloud tgt = Prepare(target);
    MethodOutput out;
    out.path = "fpfh";
    if (src.points.size() < 3 || tgt.points.size() < 3) {
      out.reason = "fewer than 3 points after voxel down-sampling";
      return out;
    }
    // Open3D's feature-matching RANSAC, in the Open3D module (seeded, one RANSAC at a time there).
    open3d_module::FeatureRansacRequest request;
    request.mutual_filter = c_.mutual_filter;
    request.max_distance_m = c_.distance_voxels * c_.voxel_m;
    request.edge_length_similarity = c_.edge_length_similarity;
    request.max_iterations = c_.max_iterations;
    request.confidence = c_.confidence;
    request.seed = static_cast<int>(c_.seed & 0x7fffffff);
    open3d_module::FeatureRansacResult result;
    open3d_module::Module().feature_ransac(src, tgt, request, &result);
    // The putative correspondences RANSAC samples from (mutual filter off): each source point
    // with its nearest target point in FPFH space. Kept for the inlier ratio under the GT pose.
    for (size_t s = 0; s < src.points.size(); ++s) {
      const int t = result.nearest_target[s];
      if (t < 0) continue;
      Correspondence c;
      c.source = src.points[s];
      c.target = tgt.points[static_cast<size_t>(t)];
      out.correspondences.push_back(c);
    }
    out.T_target_source = result.T_target_source;
    out.num_inliers = result.num_inliers;
    out.valid = result.fitness > 0 && out.num_inliers >= 3;
    std::ostringstream why;
    if (out.valid) {
      why << "fitness " << result.fitness << ", " << out.num_inliers << " of " << src.points.size()
          << " source points within " << request.max_distance_m << " m";
    } else {
      why << "RANSAC found no hypothesis passing the checkers";
    }
    out.reason = why.str();
    return out;
  }

 private:
  FpfhCloud Prepare(const Scan& scan) const {
    FpfhParams params;
    params.voxel_m = c_.voxel_m;
    params.normal_radius_voxels = c_.normal_radius_voxels;
    params.normal_max_nn = c_.normal_max_nn;
    params.feature_radius_voxels = c_.feature_radius_voxels;
    params.feature_max_nn = c_.feature_max_nn;
    return ComputeFpfh(ScanGeometry(scan, c_.min_depth_m, c_.max_depth_m), params);
  }

  FpfhConfig c_;
};

// Keypoints of one view that have a 3D point, with their descriptors (one row each).
struct LiftedFeatures {
  std::vector<Eigen::Vector3d> points;  // scan frame
  std::vector<Eigen::Vector2f> pixels;
  cv::Mat descriptors;
};

LiftedFeatures DetectAndLift(const FeatureBaselineConfig& c, const View& view) {
  cv::Mat gray;
  if (view.color.channels() == 3) {
    cv::cvtColor(view.color, gray, cv::COLOR_BGR2GRAY);
  } else {
    gray = view.color;
  }
  cv::Ptr<cv::Feature2D> detector;
  if (c.detector == "orb") {
    detector = cv::ORB::create(c.max_features);
  } else if (c.detector == "sift") {
    detector = cv::SIFT::create(c.max_features);
  } else {
    throw std::invalid_argument("FeatureBaselineConfig::detector '" + c.detector +
                                "'; expected sift or orb");
  }
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  detector->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  LiftedFeatures out;
  const ViewLift lift = LiftForView(c.lift, c.depth, 0.0);  // no noise floor: no edge test
  for (size_t k = 0; k < keypoints.size(); ++k) {
    const Eigen::Vector2f pixel(keypoints[k].pt.x, keypoints[k].pt.y);
    const auto point = LiftPixel(view, pixel, lift);
    if (!point) continue;  // invalid or out-of-range depth (or an edge, if the radius > 0)
    out.points.push_back(*point);
    out.pixels.push_back(pixel);
    out.descriptors.push_back(descriptors.row(static_cast<int>(k)));
  }
  return out;
}

// For each query row, its best match when it passes the ratio test, else -1.
std::vector<int> RatioMatches(const cv::DescriptorMatcher& matcher, const cv::Mat& query,
                              const cv::Mat& train, double ratio) {
  std::vector<int> best(static_cast<size_t>(query.rows), -1);
  if (query.empty() || train.rows < 2) return best;
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query, train, knn, 2);
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < ratio * m[1].distance) {
      best[static_cast<size_t>(m[0].queryIdx)] = m[0].trainIdx;
    }
  }
  return best;
}

}  // namespace

MethodOutput RunFeatureBaseline(const FeatureBaselineConfig& c, const Scan& source,
                                const Scan& target) {
  std::vector<LiftedFeatures> src, tgt;
  for (const View& v : source.views) src.push_back(DetectAndLift(c, v));
  for (const View& v : target.views) tgt.push_back(DetectAndLift(c, v));
  const cv::BFMatcher matcher(c.detector == "orb" ? cv::NORM_HAMMING : cv::NORM_L2);
  MethodOutput out;
  out.path = c.detector;
  std::vector<Eigen::Vector3d> from, to;
  // Every source view with every target view, pooled.
  for (size_t sv = 0; sv < src.size(); ++sv) {
    for (size_t tv = 0; tv < tgt.size(); ++tv) {
      const LiftedFeatures& s = src[sv];
      const LiftedFeatures& t = tgt[tv];
      const std::vector<int> forward = RatioMatches(matcher, s.descriptors, t.descriptors, c.ratio);
      const std::vector<int> backward =
          RatioMatches(matcher, t.descriptors, s.descriptors, c.ratio);
      for (size_t a = 0; a < forward.size(); ++a) {
        const int b = forward[a];
        if (b < 0 || backward[static_cast<size_t>(b)] != static_cast<int>(a)) continue;
        Correspondence corr;
        corr.source = s.points[a];
        corr.target = t.points[static_cast<size_t>(b)];
        corr.source_pixel = s.pixels[a];
        corr.target_pixel = t.pixels[static_cast<size_t>(b)];
        corr.view = static_cast<int>(sv);
        corr.target_view = static_cast<int>(tv);
        out.correspondences.push_back(corr);
        from.push_back(corr.source);
        to.push_back(corr.target);
      }
    }
  }
  const int n = static_cast<int>(from.size());
  std::ostringstream why;
  if (n < 3) {
    why << "only " << n << " " << c.detector << " correspondences (need 3 for RANSAC)";
    out.reason = why.str();
    return out;
  }
  const RansacResult r = EstimateRigidRansac(from, to, c.ransac, c.seed);
  if (!r.found) {
    why << "RANSAC found no non-degenerate sample in " << n << " correspondences";
    out.reason = why.str();
    return out;
  }
  out.T_target_source = r.T_target_source;
  out.num_inliers = r.num_inliers;
  const double ratio = static_cast<double>(r.num_inliers) / n;
  out.valid = r.num_inliers >= c.min_inliers && ratio >= c.min_inlier_ratio;
  why << r.num_inliers << " RANSAC inliers of " << n << " " << c.detector
      << " correspondences (ratio " << ratio << "); ";
  if (out.valid) {
    why << "valid: at least " << c.min_inliers << " inliers and ratio >= " << c.min_inlier_ratio;
  } else {
    why << "invalid: needs at least " << c.min_inliers
        << " inliers and ratio >= " << c.min_inlier_ratio;
  }
  out.reason = why.str();
  return out;
}

namespace {

class FeatureBaselineMethod : public PairMethod {
 public:
  explicit FeatureBaselineMethod(const FeatureBaselineConfig& config) : c_(config) {}
  MethodOutput Run(const Scan& source, const Scan& target) override {
    return RunFeatureBaseline(c_, source, target);
  }

 private:
  FeatureBaselineConfig c_;
};

}  // namespace

nlohmann::json FeatureBaselineConfigToJson(const FeatureBaselineConfig& c) {
  return {{"detector", c.detector},
          {"max_features", c.max_features},
          {"ratio", c.ratio},
          {"mutual", true},
          {"lift",
           {{"min_depth_m", c.depth.min_m},
            {"max_depth_m", c.depth.max_m},
            {"depth_edge_radius_px", c.lift.depth_edge_radius_px},
            {"depth_edge_relative", c.depth.edge_relative}}},
          {"ransac",
           {{"inlier_threshold_m", c.ransac.inlier_threshold_m},
            {"max_iterations", c.ransac.max_iterations},
            {"confidence", c.ransac.confidence}}},
          {"min_inliers", c.min_inliers},
          {"min_inlier_ratio", c.min_inlier_ratio},
          {"seed", c.seed}};
}

nlohmann::json FpfhConfigToJson(const FpfhConfig& c) {
  return {{"voxel_m", c.voxel_m},
          {"normal_radius_voxels", c.normal_radius_voxels},
          {"normal_max_nn", c.normal_max_nn},
          {"feature_radius_voxels", c.feature_radius_voxels},
          {"feature_max_nn", c.feature_max_nn},
          {"mutual_filter", c.mutual_filter},
          {"distance_voxels", c.distance_voxels},
          {"edge_length_similarity", c.edge_length_similarity},
          {"max_iterations", c.max_iterations},
          {"confidence", c.confidence},
          {"min_depth_m", c.min_depth_m},
          {"max_depth_m", c.max_depth_m},
          {"seed", c.seed}};
}

std::vector<Eigen::Vector3d> ScanGeometry(const Scan& scan, double min_depth_m,
                                          double max_depth_m) {
  if (!scan.points.empty()) return scan.points;
  std::vector<Eigen::Vector3d> points;
  for (const View& v : scan.views) {
    const Intrinsics& K = v.intrinsics;
    const Eigen::Matrix3d R = v.T_scan_camera.topLeftCorner<3, 3>();
    const Eigen::Vector3d t = v.T_scan_camera.topRightCorner<3, 1>();
    for (int y = 0; y < v.depth.rows; ++y) {
      const float* row = v.depth.ptr<float>(y);
      for (int x = 0; x < v.depth.cols; ++x) {
        const double z = row[x];
        if (!(z >= min_depth_m && z <= max_depth_m)) continue;
        const Eigen::Vector3d p((x - K.cx) * z / K.fx, (y - K.cy) * z / K.fy, z);
        points.push_back(R * p + t);
      }
    }
  }
  return points;
}

// The extra hypotheses are off as well: they would replace an invalid whole-image
// estimate by a geometry or clique one, which is no longer the whole-image path.
std::vector<std::string> ImagePathOverrides() {
  return {"method.object_level=false", "hypotheses.enabled=false"};
}

PipelineConfig MethodPipelineConfig(const std::string& method, PipelineConfig config) {
  if (method == "image") {
    for (const std::string& o : ImagePathOverrides()) ApplyConfigOverride(o, &config);
  }
  return config;
}

void CheckMethodName(const std::string& method) {
  if (method != "zeroreg" && method != "image" && method != "fpfh" && method != "sift" &&
      method != "orb") {
    throw MakeInputError("--method " + method,
                         "unknown method; expected zeroreg, image, fpfh, sift or orb");
  }
}

bool TakesMotionPrior(const std::string& method) {
  return method == "zeroreg" || method == "image";
}

std::set<std::string> TargetRefs(const std::vector<PairTask>& tasks) {
  std::set<std::string> refs;
  for (const PairTask& task : tasks) refs.insert(task.target_ref);
  return refs;
}

MethodFactory MakeMethodFactory(const std::string& method, const PipelineConfig& config,
                                const FpfhConfig& fpfh, const FeatureBaselineConfig& features,
                                const PreparedCacheOptions& cache) {
  CheckMethodName(method);
  if (method == "sift" || method == "orb") {
    FeatureBaselineConfig c = features;
    c.detector = method;
    return
        [c]() -> std::unique_ptr<PairMethod> { return std::make_unique<FeatureBaselineMethod>(c); };
  }
  if (method == "fpfh") {
    return [fpfh]() -> std::unique_ptr<PairMethod> { return std::make_unique<FpfhMethod>(fpfh); };
  }
  const PipelineConfig effective = MethodPipelineConfig(method, config);
  const bool image = method == "image";
  // Built now so that a bad config or a missing model is reported before any thread starts (and
  // before fragments are fused).
  const auto shared = std::make_shared<SharedPipeline>(effective, cache);
  return [shared, image]() -> std::unique_ptr<PairMethod> {
    return std::make_unique<ZeroregMethod>(shared, image);
  };
}

}  // namespace zeroreg
