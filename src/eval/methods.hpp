// The registration methods the evaluation runner compares, behind one small interface. Each
// runner thread builds its own instance (a Pipeline holds per-instance model state).
//
//   zeroreg  zeroreg::Pipeline with the given PipelineConfig (whatever path it defaults to; the
//            ablations are config overrides, see scripts/bench-ablation.sh)
//   image    the same Pipeline forced onto its whole-image feature path (paper Table 4 row (a),
//            "w/o object level"): the config overrides of ImagePathOverrides() are applied and
//            every result is checked to come from the "image" path
//   fpfh     Open3D FPFH + RANSAC with the usual 3DMatch settings (FpfhConfig)
//   sift     OpenCV SIFT / ORB keypoints of every view, ratio test both ways + mutual check,
//   orb      lifted with the view's depth, pooled over all view pairs, our deterministic RANSAC
//            with least-squares refit (FeatureBaselineConfig); a count verdict
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "eval/records.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/register.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

class PairMethod {
 public:
  virtual ~PairMethod() = default;
  virtual MethodOutput Run(const Scan& source, const Scan& target) = 0;
  // The runner's call: the scans by their refs in the list (one ref = one scan), loaded through
  // `load` when the method needs them. The zeroreg method keeps prepared scans by ref (a frame in
  // several pairs is read and perceived once); the default loads both and calls Run. `prior`
  // (eval --prior-error-deg/-m) is for the methods that take one (TakesMotionPrior); the others
  // are never given one.
  using ScanLoadFunction = std::function<Scan(const std::string& ref)>;
  virtual MethodOutput RunRefs(const std::string& source_ref, const std::string& target_ref,
                               const ScanLoadFunction& load,
                               const std::optional<MotionPrior>& /*prior*/) {
    return Run(load(source_ref), load(target_ref));
  }
};

// The prepared-scan cache of the zeroreg / image methods (eval/prepared_cache.hpp); shared by all
// runner threads. max_scans = 0 turns it off (every pair prepares both scans, as Register does).
struct PreparedCacheOptions {
  std::size_t max_scans = 32;         // PreparedScanCache::kDefaultMaxScans
  std::size_t max_bytes = 512 << 20;  // PreparedScanCache::kDefaultMaxBytes
  // The scan references that are a target in some pair of the run, when the caller knows them
  // (TargetRefs): a scan outside it is prepared as a source only (Pipeline::Prepare(scan,
  // false)), which spares ICP's normals and k-d tree of scans that are never a target. Empty =
  // unknown: every scan is prepared for both roles.
  std::set<std::string> target_refs;
};

// The target_ref of every task.
std::set<std::string> TargetRefs(const std::vector<PairTask>& tasks);

// Open3D 0.16 global registration baseline, settings of the 3DMatch literature (voxel 5 cm).
struct FpfhConfig {
  double voxel_m = 0.05;                // voxel down-sampling of both clouds
  double normal_radius_voxels = 2.0;    // normals: hybrid search radius, in voxels
  int normal_max_nn = 30;               // normals: at most this many neighbours
  double feature_radius_voxels = 5.0;   // FPFH: hybrid search radius, in voxels
  int feature_max_nn = 100;             // FPFH: at most this many neighbours
  bool mutual_filter = false;           // RANSAC on feature matching without mutual check
  double distance_voxels = 1.5;         // RANSAC inlier distance and distance checker, in voxels
  double edge_length_similarity = 0.9;  // CorrespondenceCheckerBasedOnEdgeLength
  int max_iterations = 1000000;
  double confidence = 0.999;
  // A frame (a scan without a point cloud) is the back-projection of its depth in this range.
  double min_depth_m = 0.1;
  double max_depth_m = 6.0;  // same as the fragment fusion's FuseConfig::max_depth_m
  // Open3D's global RNG is seeded with this before every RANSAC. Its RANSAC draws samples from
  // several OpenMP threads, so results are reproducible only with OMP_NUM_THREADS=1.
  std::uint64_t seed = 0;
};
nlohmann::json FpfhConfigToJson(const FpfhConfig& config);

// The image-feature baselines a user tries first (--method sift / orb).
struct FeatureBaselineConfig {
  std::string detector = "sift";  // "sift" (cv::SIFT, L2) or "orb" (cv::ORB, Hamming)
  int max_features = 4096;        // per view (cv::SIFT nfeatures / cv::ORB nfeatures)
  double ratio = 0.8;             // Lowe ratio, applied source->target and target->source
  // Keypoints are lifted with LiftPixel: depth valid and in the depth model's range. No
  // depth-edge test (radius 0), as a user's baseline would do: on HoloLens depth with 22-45 %
  // holes the pipeline's 4 px test drops most keypoints (docs/EVAL.md).
  DepthModel depth;
  LiftConfig lift = NoEdgeTest();
  // EstimateRigidRansac with these settings (inlier threshold 5 cm, refit on the inliers).
  RansacConfig ransac;
  // Verdict: counts, as such baselines have (not a geometric check of the scans).
  int min_inliers = 20;
  double min_inlier_ratio = 0.05;  // inliers / correspondences
  std::uint64_t seed = 0;          // RANSAC seed

  static LiftConfig NoEdgeTest() {
    LiftConfig c;
    c.depth_edge_radius_px = 0;
    return c;
  }
};
nlohmann::json FeatureBaselineConfigToJson(const FeatureBaselineConfig& config);

// The method's geometry for FPFH: the scan's point cloud, or, when it has none, the
// back-projection of every view's depth in [min_depth_m, max_depth_m], in the scan frame.
std::vector<Eigen::Vector3d> ScanGeometry(const Scan& scan, double min_depth_m, double max_depth_m);

// Config overrides ("section.key=value") that select the whole-image feature path of the
// Pipeline (MethodConfig::object_level = false, no extra hypotheses). --method image fails loudly
// if a result reports another path, so a renamed switch cannot silently evaluate the wrong method.
std::vector<std::string> ImagePathOverrides();

// The pipeline config a method runs with: `config`, plus ImagePathOverrides() for "image".
PipelineConfig MethodPipelineConfig(const std::string& method, PipelineConfig config);

// Known method names: "zeroreg", "image", "fpfh", "sift", "orb". Throws InputError otherwise.
void CheckMethodName(const std::string& method);

// Whether `method` registers with a motion prior (zeroreg, image: the Pipeline's MotionPrior); the
// baselines have none.
bool TakesMotionPrior(const std::string& method);

using MethodFactory = std::function<std::unique_ptr<PairMethod>()>;
// zeroreg / image run a Pipeline with MethodPipelineConfig(method, config); fpfh uses `fpfh`;
// sift / orb use `features` with detector = method.
// Builds the one Pipeline (models loaded once) and prepared-scan cache that every instance shares,
// so a bad config or missing model throws here. The factory is called once per runner thread.
MethodFactory MakeMethodFactory(const std::string& method, const PipelineConfig& config,
                                const FpfhConfig& fpfh,
                                const FeatureBaselineConfig& features = FeatureBaselineConfig(),
                                const PreparedCacheOptions& cache = PreparedCacheOptions());

// One pass of the sift / orb baseline, exposed for tests.
MethodOutput RunFeatureBaseline(const FeatureBaselineConfig& config, const Scan& source,
                                const Scan& target);

}  // namespace zeroreg
