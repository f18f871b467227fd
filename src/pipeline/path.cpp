#include "zeroreg/types.hpp"

namespace zeroreg {

bool operator==(const Path& a, const Path& b) {
  return a.source == b.source && a.estimator == b.estimator && a.moved_by_icp == b.moved_by_icp;
}

std::string PathName(const Path& path) {
  std::string name;
  switch (path.source) {
    case PathSource::kNone:
      return "";
    case PathSource::kObject:
      name = "object";
      break;
    case PathSource::kImage:
      name = "image";
      break;
    case PathSource::kImageFallback:
      name = "image-fallback";
      break;
    case PathSource::kImageRival:
      name = "image-rival";
      break;
    case PathSource::kObjectCentroids:
      name = "object-centroids";
      break;
    case PathSource::kObjectPairs:
      name = "object-pairs";
      break;
    case PathSource::kGeometry:
      name = "geometry";
      break;
    case PathSource::kImageTurned90:
      name = "image-turned-90";
      break;
    case PathSource::kImageTurned180:
      name = "image-turned-180";
      break;
    case PathSource::kImageTurned270:
      name = "image-turned-270";
      break;
    case PathSource::kViewSynthesis:
      name = "view-synthesis";
      break;
    case PathSource::kPrior:
      name = "prior";
      break;
    case PathSource::kTurned90:
      name = "turned-90";
      break;
    case PathSource::kTurned180:
      name = "turned-180";
      break;
    case PathSource::kTurned270:
      name = "turned-270";
      break;
  }
  if (path.estimator == PathEstimator::kRansac) name += " ransac";
  if (path.estimator == PathEstimator::kClique) name += " clique";
  if (path.moved_by_icp) name += " icp";
  return name;
}

}  // namespace zeroreg
