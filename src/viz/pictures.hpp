// Pictures of a registration, for people who would rather look than read:
//   objects-view<i>.png         the two images side by side, each matched object pair in the same
//                               colour (mask outline, box, label, score), unmatched objects grey;
//   correspondences-view<i>.png the point correspondences, RANSAC inliers green, outliers red
//                               (correspondences-view<i>-<j>.png: source view i, target view j,
//                               written when the fallback matched different views);
//   registered-view<i>.png      both scans' depth points projected into target view i with the
//                               estimated transform: target blue, source orange; where the two
//                               agree the colours interleave, where they disagree they split;
//   verification-view<i>.png    the geometric check (src/verify) in target view i: the target
//                               image dimmed, each source depth sample where it lands, green
//                               where the surfaces agree, red where it lies in the free space the
//                               target camera saw through, yellow where it is hidden behind;
//   synthesized-view<i>.png     view synthesis (path "view-synthesis"): source view i beside the
//                               target rendered into the virtual camera whose matches were used,
//                               the correspondences drawn between them;
//   hypotheses-view<i>.png      when several candidate transforms were checked: the
//                               registered clouds under the chosen one and its runners-up (best
//                               verification score first), each captioned with its source, score
//                               and whether the check passed;
//   ambiguous-view<i>.png       when two poses fit (RegistrationResult::alternatives): the
//                               registered clouds under each, the reported one first.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

cv::Mat DrawObjectMatches(const Scan& source, const Scan& target, const RegistrationResult& result,
                          int view);
// The correspondences between source view `source_view` and target view `target_view`.
cv::Mat DrawCorrespondences(const Scan& source, const Scan& target,
                            const RegistrationResult& result, int source_view, int target_view);
cv::Mat DrawRegisteredClouds(const Scan& source, const Scan& target,
                             const Transform& T_target_source, int view);
cv::Mat DrawVerification(const Scan& source, const Scan& target, const RegistrationResult& result,
                         const VerifyConfig& config, const DepthModel& depth, int view);

// The source view beside the target rendered into result.rendered_view's virtual camera, with
// the correspondences between them (RANSAC inliers green, outliers red); empty without one.
cv::Mat DrawSynthesizedView(const Scan& source, const Scan& target,
                            const RegistrationResult& result);

// The chosen candidate and up to max_candidates - 1 runners-up, two registered-cloud tiles a row.
cv::Mat DrawHypotheses(const Scan& source, const Scan& target, const RegistrationResult& result,
                       int view, int max_candidates);

// The poses of RegistrationResult::alternatives (an ambiguous pair), the reported one first.
cv::Mat DrawAlternatives(const Scan& source, const Scan& target, const RegistrationResult& result,
                         int view);

// Whether `file_name` is one WriteRegistrationPictures writes ("registered-view0.png",
// "correspondences-view0-2.png", ...; .jpg accepted too).
bool IsRegistrationPictureName(const std::string& file_name);

// Writes the pictures above for every view pair into `dir` (created if needed) and returns the
// file paths. Pictures of an earlier run in `dir` (IsRegistrationPictureName) are removed first, so
// that the folder shows this result only; other files are left alone. Throws InputError if the
// folder cannot be written.
// `verify` and `depth` are the check's config (the pipeline's effective `verify` and `depth`).
std::vector<std::string> WriteRegistrationPictures(const std::string& dir, const Scan& source,
                                                   const Scan& target,
                                                   const RegistrationResult& result,
                                                   const VerifyConfig& verify = {},
                                                   const DepthModel& depth = {});

}  // namespace zeroreg
