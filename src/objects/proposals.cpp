#include "objects/proposals.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace zeroreg {

std::vector<Proposal> DepthProposals(const cv::Mat& depth_m, double relative_jump,
                                     double min_area_fraction, double max_area_fraction) {
  if (depth_m.cols < 4 || depth_m.rows < 4) return {};  // nothing to propose in a few pixels
  // Work at quarter resolution: regions, not pixels, matter here, and it keeps this cheap.
  cv::Mat depth;
  cv::resize(depth_m, depth, depth_m.size() / 4, 0, 0, cv::INTER_NEAREST);
  cv::Mat region(depth.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      const float z = depth.at<float>(y, x);
      if (z <= 0) continue;
      bool edge = false;
      for (int dy = -1; dy <= 1 && !edge; ++dy) {
        for (int dx = -1; dx <= 1 && !edge; ++dx) {
          const int u = std::clamp(x + dx, 0, depth.cols - 1);
          const int v = std::clamp(y + dy, 0, depth.rows - 1);
          const float n = depth.at<float>(v, u);
          edge = n <= 0 || std::abs(n - z) > relative_jump * z;
        }
      }
      if (!edge) region.at<uchar>(y, x) = 255;
    }
  }
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(region, labels, stats, centroids, 8, CV_32S);
  const double total = static_cast<double>(depth.total());
  std::vector<Proposal> proposals;
  for (int k = 1; k < count; ++k) {
    const double area = stats.at<int>(k, cv::CC_STAT_AREA) / total;
    if (area < min_area_fraction || area > max_area_fraction) continue;
    cv::Mat small = labels == k;
    Proposal p;
    cv::resize(small, p.mask, depth_m.size(), 0, 0, cv::INTER_NEAREST);
    const cv::Rect box = cv::boundingRect(p.mask);
    p.detection.box = cv::Rect2f(box);
    p.detection.label = kProposalLabel;
    p.detection.score = static_cast<float>(area);
    proposals.push_back(std::move(p));
  }
  // Largest first, as detectors sort by score.
  std::stable_sort(proposals.begin(), proposals.end(), [](const Proposal& a, const Proposal& b) {
    return a.detection.score > b.detection.score;
  });
  return proposals;
}

Eigen::VectorXd ColourHistogram(const cv::Mat& bgr, const cv::Mat& mask) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  Eigen::VectorXd histogram = Eigen::VectorXd::Zero(8 * 4 * 4);
  for (int y = 0; y < hsv.rows; ++y) {
    const uchar* m = mask.ptr<uchar>(y);
    const cv::Vec3b* p = hsv.ptr<cv::Vec3b>(y);
    for (int x = 0; x < hsv.cols; ++x) {
      if (m[x] == 0) continue;
      const int h = std::min(7, p[x][0] * 8 / 180), s = p[x][1] / 64, v = p[x][2] / 64;
      histogram(h * 16 + s * 4 + v) += 1.0;
    }
  }
  const double norm = histogram.norm();
  return norm > 0 ? Eigen::VectorXd(histogram / norm) : histogram;
}

void TopUpWithProposals(const View& view, const ObjectsConfig& objects, const ViewLift& lift,
                        std::vector<ObjectObservation>* found) {
  if (objects.proposals_below <= 0) return;
  int usable = 0;
  cv::Mat covered(view.depth.size(), CV_8U, cv::Scalar(0));
  for (const ObjectObservation& o : *found) {
    if (o.mask.empty()) continue;
    covered |= o.mask;
    if (static_cast<int>(LiftMask(view, o.mask, objects, lift).size()) >= objects.min_points) {
      ++usable;
    }
  }
  if (usable >= objects.proposals_below) return;
  for (Proposal& p : DepthProposals(view.depth)) {
    const double area = cv::countNonZero(p.mask);
    cv::Mat inside;
    cv::bitwise_and(p.mask, covered, inside);
    if (area <= 0 || cv::countNonZero(inside) > 0.5 * area) continue;
    ObjectObservation o;
    o.detection = p.detection;
    o.mask = std::move(p.mask);
    found->push_back(std::move(o));
  }
}

}  // namespace zeroreg
