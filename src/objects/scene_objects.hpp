// Objects of one scan (paper §3.2, "Object and Feature Projection"): every detection's mask is
// back-projected through depth and the view's pose into the scan frame; observations of the same
// object in different views are associated (3D overlap and compatible label) into one object; with
// k >= 2 views only objects seen in at least two views are kept; semantic features are averaged
// over the views (f_avg = 1/k sum f_i).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "estimate/lift.hpp"
#include "objects/appearance.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// One detection in one view, with its mask and 3D points.
struct ObjectObservation {
  int view = 0;
  Detection detection;
  cv::Mat mask;                         // CV_8UC1, view size, nonzero inside
  Eigen::VectorXd semantic;             // semantic feature of the label (may be empty)
  Appearance appearance;                // image descriptor of the mask pixels (may be empty)
  std::vector<Eigen::Vector3d> points;  // scan frame, metres (sub-sampled mask pixels)
};

// An object of the scan: the association of one or more observations.
struct SceneObject {
  std::string label;
  float score = 0.0f;                   // best detection score among its observations
  Eigen::VectorXd semantic;             // mean of the observations' semantic features
  Appearance appearance;                // MeanAppearance of the observations' descriptors
  std::vector<Eigen::Vector3d> points;  // union of the observations' points, voxel-thinned
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<int> observations;  // indices into SceneObjects::observations
  std::vector<int> views;         // distinct views it was seen in, ascending
};

struct SceneObjects {
  std::vector<ObjectObservation> observations;
  std::vector<SceneObject> objects;
};

// Back-projects the mask pixels on a grid of stride `config.pixel_stride` that have usable depth
// (LiftPixel: valid, not on a depth edge).
std::vector<Eigen::Vector3d> LiftMask(const View& view, const cv::Mat& mask,
                                      const ObjectsConfig& objects, const ViewLift& lift);

// Associates the observations of a scan with `num_views` views into objects (see file comment).
// Two observations may merge only when, besides label and overlap, their appearance descriptors
// (when both have comparable ones) have cosine >= config.association_min_appearance.
// Deterministic: observations are visited in order and merged greedily.
std::vector<SceneObject> AssociateObservations(const std::vector<ObjectObservation>& observations,
                                               int num_views, const ObjectsConfig& config);

// A (n x m): cosines of the objects' appearance descriptors; comparable (n x m): 1 where both have
// descriptors of one kind, else 0 (and A = 0). The inputs of the appearance-aware NodeSimilarity.
void AppearanceCosines(const std::vector<SceneObject>& source,
                       const std::vector<SceneObject>& target, Eigen::MatrixXd* cosine,
                       Eigen::MatrixXd* comparable);

// Fraction of the smaller point set's voxels (edge config.association_voxel_m) that the other set
// also occupies.
double VoxelOverlap(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                    double voxel_m);

}  // namespace zeroreg
