// Class-agnostic object proposals for the "w/o detection" ablation: regions of the depth
// image bounded by depth discontinuities, with a colour-histogram appearance feature standing in
// for the label's CLIP feature, so that objects are matched by graph structure and appearance.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "detect/detector.hpp"
#include "estimate/lift.hpp"
#include "objects/scene_objects.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// The label every proposal carries: no class, so no CLIP row either (matched by label equality
// and appearance).
inline constexpr const char* kProposalLabel = "object";

struct Proposal {
  Detection detection;  // label "object", score = the region's share of the valid depth
  cv::Mat mask;         // CV_8UC1, image size
};

// Connected regions of valid depth separated by jumps larger than `relative_jump` x depth,
// keeping regions covering between min_area_fraction and max_area_fraction of the image (large
// ones are walls, floors, table tops: structure, not objects).
std::vector<Proposal> DepthProposals(const cv::Mat& depth_m, double relative_jump = 0.03,
                                     double min_area_fraction = 0.005,
                                     double max_area_fraction = 0.25);

// L2-normalised 8x4x4 HSV histogram of the masked pixels (appearance feature, 128-d).
Eigen::VectorXd ColourHistogram(const cv::Mat& bgr, const cv::Mat& mask);

// When fewer than objects.proposals_below of `found` (a view's segmented detections)
// lift to at least objects.min_points points, appends the view's DepthProposals that lie at most
// half inside the detections' masks (label "object"; masks and boxes as DepthProposals makes
// them). Does nothing when proposals_below is 0.
void TopUpWithProposals(const View& view, const ObjectsConfig& objects, const ViewLift& lift,
                        std::vector<ObjectObservation>* found);

}  // namespace zeroreg
