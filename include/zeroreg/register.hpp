// The one-call API: zeroreg::Register(source, target, config).
//
//   zeroreg::Scan source = zeroreg::LoadScan("../shared/data/7scenes-redkitchen@20");
//   zeroreg::Scan target = zeroreg::LoadScan("../shared/data/7scenes-redkitchen@0");
//   zeroreg::RegistrationResult r = zeroreg::Register(source, target);
//   if (r.valid) use(r.T_target_source); else log(r.reason);
//
// For many pairs, build one Pipeline (it loads the models once) and call Register repeatedly.
// When a scan is in several pairs (a sequence, a loop-closure search), prepare it once and
// register the prepared scans: everything that depends on one scan alone is then done once.
//
//   zeroreg::Pipeline pipeline(config);
//   const zeroreg::PreparedScan a = pipeline.Prepare(scan_a), b = pipeline.Prepare(scan_b);
//   zeroreg::RegistrationResult r = pipeline.Register(a, b);  // bit-identical to (scan_a, scan_b)
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// One scan as a Pipeline perceived it (Pipeline::Prepare): per view the features with their 3D
// points, the detections, masks and objects, and the scan's geometry for the later stages (surface
// samples of the verification, the thinned clouds, normals and k-d trees of ICP), plus the scan
// itself (its views' images are shared with the Scan it was made from, as cv::Mat copies are:
// do not write into them afterwards). Opaque and immutable: copies share the data, and one
// prepared scan may be used by several threads at once. Usable only with the Pipeline that made it.
class PreparedScan {
 public:
  PreparedScan();  // empty: Register refuses it
  ~PreparedScan();
  PreparedScan(const PreparedScan&);
  PreparedScan& operator=(const PreparedScan&);

  bool empty() const;
  const Scan& scan() const;  // throws std::logic_error when empty
  // Wall time of preparing it, per stage (features, detect, segment, objects, geometry), ms.
  const std::vector<StageTime>& timings() const;
  // Approximate heap memory held beyond the scan's images and points (features, masks, clouds),
  // bytes; what a cache of prepared scans budgets. It grows once when the scan is first the source
  // of a pair that needs its turned images' features (hypotheses.turned_images).
  std::size_t MemoryBytes() const;

  struct Data;

 private:
  friend class Pipeline;
  friend const Data* PreparedScanData(const PreparedScan& prepared);  // src/pipeline/prepared.hpp
  std::shared_ptr<const Data> data_;
};

// What the caller already knows of the pose (odometry, an IMU, the previous loop closure): a
// result is valid only within max_rotation_deg and max_translation_m of T_target_source (rotation
// angle and translation of inv(prior) * T). Scans with symmetric content (a box seen from
// opposite sides, a long table from both ends) agree as well under a flipped pose as under the
// true one, or better, and no test of the two scans alone can tell them apart
// (BENCHMARKS.md "Pairs that share nothing, or little"); the prior can. When no source gives a
// valid pose within it, ICP from the prior itself is tried (path "prior icp") and judged by the
// same check. The defaults are the benchmark's own "right" (15 deg, 30 cm).
struct MotionPrior {
  Transform T_target_source = Transform::Identity();
  double max_rotation_deg = 15.0;
  double max_translation_m = 0.30;
};

// Whether `result` is the motion prior itself or ICP from it (paths "prior" and "prior icp"),
// rather than the estimate of a correspondence source.
bool ComesFromMotionPrior(const RegistrationResult& result);

class Pipeline {
 public:
  // Resolves and verifies the model files and loads them. Throws InputError on a bad config or a
  // missing/corrupt model.
  explicit Pipeline(const PipelineConfig& config);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Throws InputError when a scan cannot be used at all (no views, empty or mismatched images).
  // A registration that fails is returned with valid = false and a reason, never as a silent
  // identity.
  // Prepares both scans (concurrently when config.threads >= 2) and registers them.
  // With a prior, only a pose within it can be valid (MotionPrior).
  RegistrationResult Register(const Scan& source, const Scan& target,
                              const std::optional<MotionPrior>& prior = std::nullopt) const;

  // Everything of the pipeline that depends on `scan` alone. Throws InputError as Register does.
  // Thread-safe: several threads may prepare and register with one Pipeline at once.
  // as_target = false is for a scan that will only be a source: what only a target needs (ICP's
  // normals and k-d tree) is then not made now but the first time the scan is a target, once,
  // so it may still be one. Registrations are the same bit for bit either way.
  PreparedScan Prepare(const Scan& scan, bool as_target = true) const;
  // The same result, bit for bit, as Register(source.scan(), target.scan()), without redoing the
  // per-scan work; the timings hold only the per-pair stages. Throws InputError for an empty
  // prepared scan or one made by another Pipeline.
  RegistrationResult Register(const PreparedScan& source, const PreparedScan& target,
                              const std::optional<MotionPrior>& prior = std::nullopt) const;

  const PipelineConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

RegistrationResult Register(const Scan& source, const Scan& target,
                            const PipelineConfig& config = PipelineConfig(),
                            const std::optional<MotionPrior>& prior = std::nullopt);

}  // namespace zeroreg
