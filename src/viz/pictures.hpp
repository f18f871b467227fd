// Pictures of a registration, for people who would rather look than read:
//   objects-view<i>.png         the two images side by side, each matched object pair in the same
//                               colour (mask outline, box, label, score), unmatched objects grey;
//   correspondences-view<i>.png the point correspondences, RANSAC inliers green, outliers red
//                               (correspondences-view<i>-<j>.png: source view i, target view j,
//                               written when the fallback matched different views);
//   registered-view<i>.png      both scans' depth points projected into target view i with the
//                               estimated transform: target blue, source orange; where the two
//                               agree the colours interleave, where they disagree they split.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

cv::Mat DrawObjectMatches(const Scan& source, const Scan& target, const RegistrationResult& result,
                          int view);
// The correspondences between source view `source_view` and target view `target_view`.
cv::Mat DrawCorrespondences(const Scan& source, const Scan& target,
                            const RegistrationResult& result, int source_view, int target_view);
cv::Mat DrawRegisteredClouds(const Scan& source, const Scan& target,
                             const Transform& T_target_source, int view);

// Writes the pictures above for every view pair into `dir` (created if needed) and returns the
// file paths. Throws InputError if the folder cannot be written.
std::vector<std::string> WriteRegistrationPictures(const std::string& dir, const Scan& source,
                                                   const Scan& target,
                                                   const RegistrationResult& result);

}  // namespace zeroreg
