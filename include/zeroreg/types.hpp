// The data model shared by every stage (DESIGN.md §3).
//
// Conventions, written down once:
// - Units: metres for 3D, pixels for 2D, milliseconds for timings.
// - Camera frame: x right, y down, z forward (OpenCV / 3DMatch / 7-Scenes convention).
// - A transform named T_a_b maps coordinates expressed in frame b into frame a: x_a = T_a_b * x_b.
//   A dataset pose file is T_world_camera. A 3DMatch gt.log entry "i j" is T_i_j (maps fragment j
//   into fragment i). The registration result is T_target_source.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace zeroreg {

using Transform = Eigen::Matrix4d;  // rigid transform, homogeneous 4x4, named T_to_from

struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  int width = 0, height = 0;              // pixels
};

// One posed RGB-D image.
struct View {
  std::string name;  // file or frame name, used in messages and pictures
  // The colour image file the view was read from (empty when built in memory). Precomputed
  // detections and masks are looked up by its stem (docs/PERCEPTION.md); without it, by `name`.
  std::string color_file;
  cv::Mat color;  // CV_8UC3, BGR
  cv::Mat depth;  // CV_32FC1, metres, 0 = invalid; same size as color
  Intrinsics intrinsics;
  Transform T_scan_camera = Transform::Identity();  // camera -> scan frame
  // Ground truth, when the dataset has it: camera -> world. Used only for evaluation.
  std::optional<Transform> T_world_camera_gt;
};

// What is registered: posed views plus the point cloud they describe (may be empty, in which case
// the views' depth is the geometry). One RGB-D frame is a scan with one view and identity pose; a
// 3DMatch fragment is a TSDF fusion of 50 frames with k chosen views.
struct Scan {
  std::string name;
  std::vector<View> views;
  std::vector<Eigen::Vector3d> points;  // scan frame, metres
  std::vector<Eigen::Vector3d> colors;  // optional, RGB in [0,1], same size as points or empty
  // Ground truth, when known: scan -> world. Used only for evaluation.
  std::optional<Transform> T_world_scan_gt;
};

// A 3D correspondence between the two scans, with the pixels it came from.
struct Correspondence {
  Eigen::Vector3d source = Eigen::Vector3d::Zero();  // source scan frame, metres
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // target scan frame, metres
  Eigen::Vector2f source_pixel = Eigen::Vector2f::Zero();
  Eigen::Vector2f target_pixel = Eigen::Vector2f::Zero();
  int view = 0;         // source view the source pixel is in
  int target_view = 0;  // target view the target pixel is in (equal to `view` on the object level)
  float score = 0.0f;   // matcher confidence (cosine similarity or match probability)
};

// One detection of an object in one view (for the result and the pictures).
struct ObjectView {
  int view = 0;
  cv::Rect2f box;                  // pixels
  float score = 0.0f;              // detector confidence
  std::vector<cv::Point> outline;  // mask outline (largest contour), pixels
};

// An object found in a scan (paper §3.2): label, 3D centroid and where it was seen.
struct ObjectSummary {
  std::string label;
  float score = 0.0f;                                  // best detection score
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // scan frame, metres
  int num_points = 0;                                  // points.size()
  // The object's surface: its masks' depth pixels lifted into the scan frame (metres), one per
  // objects.point_voxel_m voxel (2 cm). Not written to the JSON result (the counts are).
  std::vector<Eigen::Vector3d> points;
  std::vector<ObjectView> views;
};

// A matched object pair (paper §3.3, Eq. 2), indices into the result's object lists.
struct ObjectMatchSummary {
  int source = 0;
  int target = 0;
  double node_similarity = 0.0;  // C = 1 + cos of the semantic features
  int num_correspondences = 0;   // point correspondences found inside the pair (§3.4)
  // Most of the point matches between the two objects that one rigid motion explains
  // (object_match.min_point_support); -1 when not measured (point support
  // and motion agreement both off). Counted before
  // overlapping masks are deduplicated, so it can exceed num_correspondences.
  int point_support = -1;
};

// One row of per-stage wall time, in milliseconds, in pipeline order.
struct StageTime {
  std::string stage;
  double ms = 0.0;
};

// The geometric check of a returned transform (src/verify/verify.hpp, docs/CONFIG.md "verify"):
// each scan's depth rendered into the other scan's views under T_target_source.
struct VerificationResult {
  bool ran = false;     // false when verification is disabled (the count verdict decides)
  bool passed = false;  // the scans agree under the transform
  std::string reason;   // why it failed, or the evidence in one line
  // Fraction of each scan's sampled surface that coincides with the other's surface within the
  // depth tolerance: the smaller and the larger of the two directions.
  double overlap = 0.0;
  double overlap_max = 0.0;
  // Violations / (agreements + violations): surface of one scan lying in space the other camera
  // saw through. Near 0 for a correct transform.
  double violation = 0.0;
  double residual_rms_m = 0.0;  // RMS depth difference over the agreeing samples
  double score = 0.0;  // mean per sample of (1 - (r/tau)^2 if agreeing, -1 if violating, else 0)
  // Fraction of the agreeing source surface that leaves the target's surface when the estimate is
  // moved by VerifyConfig::probe_translation_m along its least constrained motion (the smaller of
  // the two senses); near 0 = the geometry does not fix that motion (a plane, a corridor).
  double probe_contradicted = 0.0;
  bool degenerate = false;
  // Spearman rank correlation of the grey levels of the two images at the samples where the
  // depth agrees (both directions pooled): near 1 when the surfaces that coincide are the same
  // surfaces (exposure changes keep the order of brightness), near 0 or below when geometry alone
  // lines up unrelated ones. NaN when fewer than 30 agreeing samples have colour in both scans.
  double brightness_rank_correlation = 0.0;
  int source_samples = 0, target_samples = 0;  // sampled depth pixels of each scan
};

// One of the poses that fit an ambiguous pair (RegistrationResult::alternatives): the check's
// measures under it and the evidence that speaks for it.
struct Alternative {
  std::string name;  // the candidate it comes from, e.g. "image-fallback icp", "turned 180 icp"
  Transform T_target_source = Transform::Identity();
  double score = 0.0;                        // VerificationResult::score
  double overlap = 0.0;                      // VerificationResult::overlap
  double violation = 0.0;                    // VerificationResult::violation
  double brightness_rank_correlation = 0.0;  // NaN when too few samples had colour
  int num_inliers = 0;                       // correspondences supporting it (0 for a turned pose)
  double apart_m = 0.0;        // RMS distance over the source surface from the first alternative
  bool outside_prior = false;  // beyond the caller's MotionPrior (so the prior rules it out)
};

// One candidate transform the pipeline considered (e.g. RANSAC's and ICP's), with its check.
struct CandidateSummary {
  std::string name;  // e.g. "object ransac", "object icp", "image-fallback ransac"
  Transform T_target_source = Transform::Identity();
  double score = 0.0;  // VerificationResult::score
  bool passed = false;
  bool chosen = false;
  bool outside_prior = false;  // passed, but beyond the caller's MotionPrior (so not valid)
};

// A camera the target scan was rendered into (src/synthesis): the source view whose image was
// matched against the rendering, where the camera was put, and what put it there.
struct RenderedCamera {
  int source_view = 0;
  Transform T_target_camera = Transform::Identity();  // virtual camera -> target scan frame
  Intrinsics intrinsics;                              // the source view's
  std::string from;  // the hypothesis it was rendered from ("image-fallback ransac", "orbit ...")
};

// Which test made a result not valid, with what it measured and the threshold it missed (units
// per test below). RegistrationResult::reason is the prose; this is what decides.
enum class RefusalTest {
  kNone,                // valid
  kFewCorrespondences,  // correspondences; 3 (a rigid transform needs three)
  kFewInliers,          // inliers of the estimate; ransac.min_inliers
  kInliersOnALine,      // spread of the inliers across their line (m); ransac.min_inlier_spread_m
  kLowInlierRatio,      // inliers / correspondences; ransac.min_inlier_ratio
  kLittleDepth,         // the smaller scan's surface samples; verify.min_points
  kLowOverlap,          // overlap fraction under the transform; verify.min_overlap
  kFreeSpaceViolation,  // free-space violation fraction; verify.max_violation
  kOutsidePrior,        // rotation (deg) or, when that is within, translation (m) from the prior;
                        // the prior's tolerance in the same unit
  kDegenerate,          // probe_contradicted; verify.min_probe_contradicted (a source whose
                        // correspondences cannot fix the motion the geometry leaves open)
  kImagesDisagree,      // brightness rank correlation; hypotheses.min_brightness_rank_correlation
  kAnotherPosePasses,   // RMS apart of the estimate and ICP's pose, both accepted (m);
                        // refine.max_distance_coarse_m
  kAmbiguous,           // RMS apart over the source surface of the two poses that fit (m);
                        // refine.max_distance_coarse_m (RegistrationResult::alternatives)
  kMirrorImage,         // distinctive matches of the source's images flipped left-right; the
                        // larger of verify.mirror_min_matches and verify.mirror_ratio times the
                        // matches as given (src/pipeline/handedness.hpp)
};
struct Refusal {
  RefusalTest test = RefusalTest::kNone;
  double measured = 0.0;
  double threshold = 0.0;
};
// The name of a test as the JSON result and Python write it ("few_inliers", ...; "" for kNone).
const char* RefusalTestName(RefusalTest test);
// One sentence made from the fields (empty for kNone).
std::string DescribeRefusal(const Refusal& refusal);

// Which source produced the transform (RegistrationResult::path). PathName makes the string the
// JSON result, the eval records and Python carry ("object", "image clique", "prior icp").
enum class PathSource {
  kNone,             // "": nothing was estimated
  kObject,           // "object": correspondences inside matched objects (paper §3.4)
  kImage,            // "image": whole-image features (Table 4 row a; or the extra source)
  kImageFallback,    // "image-fallback": the whole images instead of a failed object level
  kImageRival,       // "image-rival": the whole images judged against a doubtful object estimate
  kObjectCentroids,  // "object-centroids": the matched objects' centroids (Table 4 row b)
  kObjectPairs,      // "object-pairs": every same-label object pair's centroids
  kGeometry,         // "geometry": FPFH matches of the scans' depth
  kImageTurned90,    // "image-turned-90": the source's images turned by a quarter turn
  kImageTurned180,   // "image-turned-180"
  kImageTurned270,   // "image-turned-270"
  kViewSynthesis,    // "view-synthesis": the source's image against the target rendered
  kPrior,            // "prior": ICP from the caller's MotionPrior
  kTurned90,         // "turned-90": the reported pose turned about the vertical (ambiguity test)
  kTurned180,        // "turned-180"
  kTurned270,        // "turned-270"
};
// The estimator an extra source names after its source ("image clique"); kMethod: the method's
// own flow (ransac.estimator), whose path names none.
enum class PathEstimator { kMethod, kRansac, kClique };
struct Path {
  PathSource source = PathSource::kNone;
  PathEstimator estimator = PathEstimator::kMethod;
  bool moved_by_icp = false;  // a source's starting pose moved by ICP ("prior icp")
};
bool operator==(const Path& a, const Path& b);
inline bool operator!=(const Path& a, const Path& b) { return !(a == b); }
// The path's name, e.g. "object", "image-turned-180 ransac", "prior icp" ("" for kNone).
std::string PathName(const Path& path);

struct RegistrationResult {
  Transform T_target_source = Transform::Identity();
  bool valid = false;
  // The check (and count test) passed, but the pose lies beyond the caller's MotionPrior, so it
  // is not valid; false without a prior.
  bool outside_prior = false;
  std::string reason;  // why valid is false (or a short summary when true)
  Refusal refusal;     // the test that refused it, as data; test == kNone exactly when valid
  Path path;           // which source produced the transform (PathName: e.g. "image")
  int num_keypoints_source = 0;
  int num_keypoints_target = 0;
  int num_correspondences = 0;  // 3D correspondences given to the estimator
  // Correspondences within the RANSAC distance of the returned transform (after ICP refinement,
  // when it ran and was kept).
  int num_inliers = 0;
  double inlier_ratio = 0.0;  // num_inliers / num_correspondences
  double inlier_rmse = 0.0;   // metres, over the RANSAC inliers
  // Spread of the inliers across their main direction (std. dev. along the second principal axis,
  // metres): small when they lie on a line, which leaves a rotation undetermined.
  double inlier_spread_m = 0.0;
  int ransac_iterations = 0;
  // RANSAC's count test (RansacConfig: inliers, inlier ratio, spread) passed: the correspondences
  // support an estimate. With verification on, `valid` also needs the geometric check.
  bool count_test_passed = false;
  std::vector<Correspondence> correspondences;
  std::vector<bool> is_inlier;  // parallel to correspondences
  std::vector<ObjectSummary> source_objects;
  std::vector<ObjectSummary> target_objects;
  std::vector<ObjectMatchSummary> object_matches;
  // Matches of Eq. 2 that object_match.motion_agreement or
  // object_match.agree_with_result removed (not in object_matches).
  int rejected_object_matches = 0;
  std::vector<StageTime> timings;
  // The geometric check of T_target_source; with verification on it decides `valid`.
  VerificationResult verification;
  // Every transform that was checked, in the order they were made (the chosen one marked).
  std::vector<CandidateSummary> candidates;
  // Two (or more) poses farther apart than the check can tell fit the scans about equally well
  // (the arbiter's ambiguity test, docs/ARCHITECTURE.md): `valid` is false, refusal kAmbiguous,
  // and `alternatives` holds each pose, the one T_target_source reports first. With a motion
  // prior that rules all but one out, the result is valid, not ambiguous, and the ruled-out ones
  // stay listed (outside_prior).
  bool ambiguous = false;
  std::vector<Alternative> alternatives;
  // Path "view-synthesis": the virtual camera the target was rendered into; the correspondences'
  // target pixels are pixels of that rendering (target_view -1), their source pixels are in
  // source view `source_view`.
  std::optional<RenderedCamera> rendered_view;
};

}  // namespace zeroreg
