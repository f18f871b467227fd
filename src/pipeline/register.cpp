#include "zeroreg/register.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "estimate/icp.hpp"
#include "estimate/max_clique.hpp"
#include "estimate/rigid_ransac.hpp"
#include "estimate/working_scale.hpp"
#include "eval/metrics.hpp"
#include "features/feature_extractor.hpp"
#include "inference/onnx_model.hpp"
#include "io/text_parsing.hpp"
#include "object_match/result_support.hpp"
#include "parallel/run_both.hpp"
#include "pipeline/arbiter.hpp"
#include "pipeline/image_source.hpp"
#include "pipeline/input_checks.hpp"
#include "pipeline/judge.hpp"
#include "pipeline/object_correspondences.hpp"
#include "pipeline/prepared.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "verify/verify.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/json.hpp"

namespace zeroreg {

PreparedScan::PreparedScan() = default;
PreparedScan::~PreparedScan() = default;
PreparedScan::PreparedScan(const PreparedScan&) = default;
PreparedScan& PreparedScan::operator=(const PreparedScan&) = default;
bool PreparedScan::empty() const { return data_ == nullptr; }

const PreparedScan::Data* PreparedScanData(const PreparedScan& prepared) {
  return prepared.data_.get();
}
const Scan& PreparedScan::scan() const {
  if (!data_) throw std::logic_error("PreparedScan::scan() called on an empty prepared scan");
  return data_->original ? *data_->original : data_->scan;
}
const std::vector<StageTime>& PreparedScan::timings() const {
  static const std::vector<StageTime> kNone;
  return data_ ? data_->timings : kNone;
}
std::size_t PreparedScan::MemoryBytes() const {
  return data_ ? data_->memory_bytes + data_->turned_bytes.load() : 0;
}

namespace {

// Model files of the configured detector, verified against the repo's sha256 list.
// PicoDet: only the file of the configured engine (the verbatim export on ONNX Runtime, the
// Clip-rewritten copy on OpenCV DNN).
DetectorModelPaths ResolveDetectorModels(const DetectorConfig& config,
                                         const InferenceConfig& inference,
                                         const std::string& assets) {
  DetectorModelPaths paths;
  if (config.backend == "yolox" || config.backend == "ensemble") {
    paths.yolox_onnx = RequireAsset(assets, "yolox_nano_coco/yolox_nano.onnx");
    paths.yolox_classes = RequireAsset(assets, "yolox_nano_coco/coco_classes.txt");
  }
  if (config.backend == "picodet" || config.backend == "ensemble") {
    if (ResolveEngine(inference) == InferenceEngine::kOpenCv) {
      paths.picodet_opencv_onnx =
          RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.opencv.onnx");
    } else {
      paths.picodet_onnx = RequireAsset(assets, "picodet_s_416_coco/picodet_s_416_coco.onnx");
    }
    paths.picodet_classes = RequireAsset(assets, "picodet_s_416_coco/coco.names");
  }
  if (config.backend == "darknet") {
    paths.darknet_cfg = RequireAsset(assets, "yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.cfg");
    paths.darknet_weights =
        RequireAsset(assets, "yolo_fastest_1.1_xl_coco/yolo-fastest-1.1-xl.weights");
    paths.darknet_classes = RequireAsset(assets, "yolo_fastest_1.1_xl_coco/coco_classes.txt");
  }
  return paths;
}

// Whether any configured stage reads a model file (SIFT + file detections + no CLIP need none).
bool NeedsAssets(const PipelineConfig& c) {
  if (c.features.backend != "sift") return true;
  if (!c.method.object_level) return false;
  return c.detector.backend != "file" || c.method.clip || c.segmenter.backend == "sam";
}

// Heap bytes of what a prepared scan holds (images, points, features, masks, clouds).
std::size_t PreparedBytes(const Prepared& p) {
  std::size_t bytes = p.scan.points.size() * sizeof(Eigen::Vector3d) +
                      p.scan.colors.size() * sizeof(Eigen::Vector3d);
  for (const View& v : p.scan.views) {
    bytes += v.color.total() * v.color.elemSize() + v.depth.total() * v.depth.elemSize();
  }
  for (const LiftedFeatures& f : p.perceived->view_features) bytes += LiftedFeaturesBytes(f);
  for (const ObjectObservation& o : p.perceived->objects.observations) {
    bytes += o.mask.total() * o.mask.elemSize() + o.points.size() * sizeof(Eigen::Vector3d);
  }
  for (const SceneObject& o : p.perceived->objects.objects) {
    bytes += o.points.size() * sizeof(Eigen::Vector3d);
  }
  for (const auto& rows : p.perceived->observation_rows) bytes += rows.size() * sizeof(int);
  bytes += p.surface.size() * sizeof(SurfacePoint) + p.icp.MemoryBytes();
  return bytes;
}

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// object_match.agree_with_result: a valid result keeps the object matches its transform T
// supports (TransformSupportsMatch; `points` are the matches' point matches, parallel to
// result->object_matches); the others are counted as rejected.
void KeepObjectMatchesThatMoveWith(const Transform& T, const std::vector<MatchMotion>& points,
                                   double threshold_m, RegistrationResult* result) {
  if (points.size() != result->object_matches.size()) return;
  std::vector<ObjectMatchSummary> kept;
  for (size_t i = 0; i < points.size(); ++i) {
    const ObjectMatchSummary& m = result->object_matches[i];
    if (TransformSupportsMatch(T, points[i], result->source_objects[m.source].points,
                               result->target_objects[m.target].points, threshold_m)) {
      kept.push_back(m);
    }
  }
  result->rejected_object_matches += static_cast<int>(result->object_matches.size() - kept.size());
  result->object_matches = std::move(kept);
}

std::atomic<std::uint64_t> g_next_pipeline_id{1};

}  // namespace

std::size_t LiftedFeaturesBytes(const LiftedFeatures& f) {
  return f.features.keypoints.size() * (sizeof(Eigen::Vector2f) + sizeof(float)) +
         static_cast<std::size_t>(f.features.descriptors.size()) * sizeof(float) +
         f.points.size() * sizeof(Eigen::Vector3d);
}

struct Pipeline::Impl {
  PipelineConfig config;
  std::uint64_t id = g_next_pipeline_id++;
  std::unique_ptr<FeatureExtractor> extractor;
  std::unique_ptr<DescriptorMatcher> matcher;
  std::unique_ptr<Detector> detector;
  std::unique_ptr<Segmenter> segmenter;
  std::unique_ptr<TextEmbedder> embedder;
  std::unique_ptr<CorrespondenceSource> correspondence_source;

  // Prepare without the input check (the caller made it, naming the scan's role). A scan that
  // will only be a source (Register(scan, scan)) skips what only a target needs (ICP normals).
  // `k`: the working scale to prepare at (a pair's); unset: the scan's own.
  std::shared_ptr<const Prepared> PrepareChecked(const Scan& given, bool as_target = true,
                                                 std::optional<double> k = std::nullopt,
                                                 std::optional<double> distance_m = {}) const {
    auto p = std::make_shared<Prepared>();
    p->pipeline_id = id;
    p->working_distance_m = distance_m ? distance_m : WorkingDistance(given);
    p->working_scale = k ? *k : WorkingScale(p->working_distance_m, config.scale);
    if (p->working_scale != 1.0) {
      p->original = std::make_shared<const Scan>(given);
      p->scan = InWorkingUnits(given, p->working_scale);
    } else {
      p->scan = given;
    }
    const Scan& scan = p->scan;
    StageTimer perceive_timer, geometry_timer;
    const auto perceive = [&] {
      p->perceived = std::make_shared<const PerceivedScan>(
          correspondence_source->Perceive(scan, perceive_timer));
    };
    // The geometry of the later stages depends on depth alone: it is made while the models look
    // at the images.
    const auto geometry = [&] {
      geometry_timer.Restart();
      if (config.verify.enabled) p->surface = SampleSurface(scan, config.verify, config.depth);
      if (config.refine.enabled) {
        p->icp = ScanIcpGeometry(scan, IcpSchedule(config.refine, config.depth), as_target,
                                 config.refine.pixel_stride);
      }
      geometry_timer.Mark("geometry");
    };
    RunBoth(config.threads >= 2, perceive, geometry);
    p->timings = perceive_timer.times();
    for (const StageTime& t : geometry_timer.times()) p->timings.push_back(t);
    p->memory_bytes = PreparedBytes(*p);
    return p;
  }

  const Prepared& Check(const std::shared_ptr<const Prepared>& data,
                        const std::string& role) const {
    if (!data) {
      throw MakeInputError(role + " prepared scan",
                           "is empty; expected the result of Pipeline::Prepare");
    }
    if (data->pipeline_id != id) {
      throw MakeInputError(role + " prepared scan '" + data->scan.name + "'",
                           "was prepared by another Pipeline; expected one prepared by this "
                           "Pipeline (its config decided the features, objects and clouds)");
    }
    return *data;
  }

  // Everything after Prepare: §3.3-3.4 correspondences, RANSAC, verification, ICP.
  RegistrationResult RegisterPrepared(const std::shared_ptr<const Prepared>& source_ptr,
                                      const std::shared_ptr<const Prepared>& target_ptr,
                                      const std::optional<MotionPrior>& prior,
                                      StageTimer& timer) const;

  // Both scans at the pair's working scale: a scan prepared at another (its own) is prepared
  // again from the scan as given. Inside the rooms' range both are 1 and nothing is redone.
  RegistrationResult RegisterAtPairScale(std::shared_ptr<const Prepared> source,
                                         std::shared_ptr<const Prepared> target,
                                         const std::optional<MotionPrior>& prior,
                                         StageTimer& timer) const {
    const double k = WorkingScale(
        PairWorkingDistance(source->working_distance_m, target->working_distance_m), config.scale);
    const auto at_k = [&](std::shared_ptr<const Prepared>& p, bool as_target) {
      if (p->working_scale == k) return;
      p = PrepareChecked(p->original ? *p->original : p->scan, as_target, k, p->working_distance_m);
      for (const StageTime& st : p->timings) timer.Add(st.stage, st.ms);
    };
    at_k(source, /*as_target=*/false);
    at_k(target, /*as_target=*/true);
    RegistrationResult result =
        RegisterPrepared(source, target, PriorInWorkingUnits(prior, k), timer);
    ResultInMetres(k, prior, &result);
    return result;
  }
};

Pipeline::Pipeline(const PipelineConfig& config) : impl_(std::make_unique<Impl>()) {
  ValidateConfig(config, "config");
  impl_->config = config;
  ResolveEngine(config.inference);  // inference.engine=onnxruntime without it: fail here, named
  const std::string assets =
      NeedsAssets(config) ? ResolveAssetsDir(config.assets_dir) : config.assets_dir;
  Impl& m = *impl_;
  const auto load_features = [&] {
    m.extractor = MakeFeatureExtractor(config.features, assets, config.inference);
    m.matcher = MakeDescriptorMatcher(config.match);
  };
  if (!config.method.object_level) {
    load_features();
    m.correspondence_source = std::make_unique<ImageCorrespondenceSource>(
        *m.extractor, *m.matcher, config.lift, config.depth, WholeImageViewPairsOf(config.method),
        config.threads);
    return;
  }
  const auto load_objects = [&] {
    m.detector = MakeDetector(config.detector,
                              ResolveDetectorModels(config.detector, config.inference, assets),
                              config.inference);
    m.segmenter =
        MakeSegmenter(config.segmenter, assets, config.inference, config.seed, config.depth);
    if (config.method.clip) m.embedder = MakeTextEmbedder(config.semantics, assets);
  };
  // The model files are independent: the feature extractor is verified and loaded on a second
  // thread while the object models load here. Most of it is single-threaded (sha256 of the file,
  // ONNX Runtime's graph optimisation of a session: ~100 ms for XFeat), so the two halves
  // overlap instead of adding up. The models are the same either way; a failure of the features is
  // reported first whatever the thread count (RunBoth).
  RunBoth(config.threads >= 2, load_features, load_objects);
  m.correspondence_source = std::make_unique<ObjectCorrespondenceSource>(
      m.config, *m.extractor, *m.detector, *m.segmenter, m.embedder.get(), *m.matcher);
}

Pipeline::~Pipeline() = default;

const PipelineConfig& Pipeline::config() const { return impl_->config; }

RegistrationResult Pipeline::Impl::RegisterPrepared(
    const std::shared_ptr<const Prepared>& source_ptr,
    const std::shared_ptr<const Prepared>& target_ptr, const std::optional<MotionPrior>& prior,
    StageTimer& timer) const {
  const Prepared& source = *source_ptr;
  const Prepared& target = *target_ptr;
  CorrespondenceSet found = correspondence_source->Find(source.perceived, target.perceived, timer);
  RegistrationResult scans;  // what belongs to the scans, whichever candidate wins
  scans.source_objects = source.perceived->object_summaries;
  scans.target_objects = target.perceived->object_summaries;
  scans.object_matches = std::move(found.object_matches);
  scans.rejected_object_matches = found.rejected_object_matches;
  scans.num_keypoints_source = source.perceived->num_keypoints;
  scans.num_keypoints_target = target.perceived->num_keypoints;

  Proposal method;
  method.path.source = found.path == PathSource::kNone ? correspondence_source->path() : found.path;
  method.check_name = PathName(method.path) + " ransac";
  method.effective = config;
  // Table 4 row (b) judges a handful of centroid pairs, each off by up to a few decimetres;
  // every later step of the method (fallback, refinement, prior) uses the same thresholds.
  if (method.path.source == PathSource::kObjectCentroids) {
    method.effective.ransac.inlier_threshold_m = config.method.object_centroid_threshold_m;
    method.effective.ransac.min_inliers = 3;
  }
  const PipelineConfig method_effective = method.effective;
  WholeImageMatches whole_image(found.whole_image_fallback);
  PairInputs pair{source,        target, config,       prior,  extractor.get(),
                  matcher.get(), {},     &whole_image, &scans, &method_effective};
  if (config.hypotheses.enabled && method.path.source == PathSource::kObject) {
    pair.object_correspondences = found.correspondences;
  }
  method.correspondences = std::move(found.correspondences);
  const Judge judge(source, target, config, prior);
  Arbiter arbiter([&judge](Proposal p, StageTimer* t) { return judge.Full(std::move(p), t); }, pair,
                  timer);
  RegistrationResult result = arbiter.Decide(std::move(method), scans);
  if (config.object_match.agree_with_result && result.valid) {
    KeepObjectMatchesThatMoveWith(result.T_target_source, found.object_match_points,
                                  config.ransac.inlier_threshold_m, &result);
  }
  return result;
}

PreparedScan Pipeline::Prepare(const Scan& scan, bool as_target) const {
  CheckScan(scan, "prepared");
  PreparedScan out;
  out.data_ = impl_->PrepareChecked(scan, as_target);
  return out;
}

RegistrationResult Pipeline::Register(const PreparedScan& source, const PreparedScan& target,
                                      const std::optional<MotionPrior>& prior) const {
  const auto start = std::chrono::steady_clock::now();
  impl_->Check(source.data_, "source");
  impl_->Check(target.data_, "target");
  CheckPrior(prior);
  StageTimer timer;
  RegistrationResult result = impl_->RegisterAtPairScale(source.data_, target.data_, prior, timer);
  result.timings = timer.times();
  result.timings.push_back({"total", MillisecondsSince(start)});
  return result;
}

RegistrationResult Pipeline::Register(const Scan& source, const Scan& target,
                                      const std::optional<MotionPrior>& prior) const {
  const auto start = std::chrono::steady_clock::now();
  CheckScan(source, "source");
  CheckScan(target, "target");
  CheckPrior(prior);
  // The two scans' perception is independent: with two threads each scan is prepared on its own
  // (the models serialise their inference, so one scan's detector overlaps the other's features).
  // One working scale for both scans, from both (src/estimate/working_scale.hpp).
  const std::optional<double> source_distance = WorkingDistance(source);
  const std::optional<double> target_distance = WorkingDistance(target);
  const double k =
      WorkingScale(PairWorkingDistance(source_distance, target_distance), impl_->config.scale);
  std::shared_ptr<const Prepared> s, t;
  RunBoth(
      impl_->config.threads >= 2,
      [&] { s = impl_->PrepareChecked(source, /*as_target=*/false, k, source_distance); },
      [&] { t = impl_->PrepareChecked(target, /*as_target=*/true, k, target_distance); });
  StageTimer timer;
  // Per-scan stages first, summed over both scans (when they ran at once they add up to more
  // than the wall time), then the per-pair stages; "total" is the wall time of the call.
  for (const Prepared* p : {s.get(), t.get()}) {
    for (const StageTime& st : p->timings) timer.Add(st.stage, st.ms);
  }
  RegistrationResult result = impl_->RegisterAtPairScale(s, t, prior, timer);
  result.timings = timer.times();
  result.timings.push_back({"total", MillisecondsSince(start)});
  return result;
}

RegistrationResult Register(const Scan& source, const Scan& target, const PipelineConfig& config,
                            const std::optional<MotionPrior>& prior) {
  return Pipeline(config).Register(source, target, prior);
}

}  // namespace zeroreg
