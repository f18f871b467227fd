// Configuration: one plain struct per stage, nested in PipelineConfig. Every field has a default
// that follows from the method or from units; the JSON keys are the field names (see
// docs/CONFIG.md). The effective config is written into every result.
#pragma once

#include <cstdint>
#include <string>

namespace zeroreg {

// Local image features (paper §3.2 "Geometric Feature Extraction").
struct FeatureConfig {
  std::string backend = "xfeat";  // "xfeat" (ONNX, default) or "sift" (no model needed)
  int max_keypoints = 4096;       // per image, strongest first (XFeat upstream top-k)
  // XFeat: minimum keypoint heatmap probability (upstream detection threshold).
  double xfeat_detection_threshold = 0.05;
  // SIFT: OpenCV contrast threshold (OpenCV default 0.04).
  double sift_contrast_threshold = 0.04;
};

// Matching descriptors between two images.
struct MatchConfig {
  std::string method = "mutual_nn";  // mutual nearest neighbours on cosine similarity
  // Matches whose descriptor cosine similarity is below this are dropped. Descriptors are
  // L2-normalised, so this is a unit-free similarity in [-1, 1].
  double min_cosine = 0.5;
};

// Lifting matched pixels to 3D with depth.
struct LiftConfig {
  double min_depth_m = 0.1;  // closer readings are sensor noise for structured-light cameras
  double max_depth_m = 8.0;  // beyond this, consumer depth is too noisy to register with
  // A pixel is on a depth edge (and skipped) when some pixel within depth_edge_radius_px differs in
  // depth by more than depth_edge_relative * depth, or is invalid. Colour and depth are not always
  // registered (7-Scenes: ~5 px), so the radius is a few pixels.
  int depth_edge_radius_px = 4;
  double depth_edge_relative = 0.05;
};

// Robust estimation of the rigid transform from 3D correspondences (paper §3.4, RANSAC).
struct RansacConfig {
  double inlier_threshold_m = 0.05;  // 3DMatch convention: 5 cm
  int max_iterations = 50000;
  double confidence = 0.99999;  // adaptive stop once this probability of an all-inlier sample
  // Verdict: the result is valid only with at least this many inliers and this inlier ratio.
  int min_inliers = 20;
  double min_inlier_ratio = 0.05;  // feature-match-recall threshold of the 3DMatch protocol
};

// Building the objects of a scan from its views' masks (paper §3.2).
struct ObjectsConfig {
  // With k >= 2 views, keep only objects seen in at least this many views (paper: 2).
  int min_views = 2;
  // Mask pixels are back-projected on a grid with this stride: 4 px keeps ~6% of the pixels,
  // plenty for a centroid and an overlap test.
  int pixel_stride = 4;
  // An observation with fewer 3D points than this is dropped (mask on invalid depth or edges).
  int min_points = 20;
  // Two observations in different views are the same object when their labels are compatible and
  // at least this fraction of the smaller one's voxels is shared (voxel edge below).
  double association_min_overlap = 0.3;
  double association_voxel_m = 0.05;
  // Labels are compatible when equal, or when their semantic cosine is at least this (synonyms).
  double compatible_label_cosine = 0.9;
  // Object point sets are thinned to one point per voxel of this edge.
  double point_voxel_m = 0.02;
};

struct PipelineConfig {
  FeatureConfig features;
  MatchConfig match;
  LiftConfig lift;
  RansacConfig ransac;
  ObjectsConfig objects;
  std::uint64_t seed = 0;  // every random step derives its seed from this
  std::string assets_dir;  // empty: --assets, then $ZEROREG_ASSETS, then <repo>/assets
};

}  // namespace zeroreg
