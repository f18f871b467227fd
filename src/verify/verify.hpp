// Geometric verification of a registration: do the two scans agree under the estimate?
//
// Each scan's depth is rendered into the other scan's views: every sampled depth pixel of one scan
// is moved by the estimate into each camera of the other scan and compared with the depth that
// camera measured at the pixel it lands on (Fig. of docs/VERIFY.md):
//   |z - d| <= tau(d)      agreement: the two surfaces coincide within the depth noise
//   z < d - tau(d)         free-space violation: the point lies in space the other camera saw
//                          through (a wrong transform puts surfaces there)
//   z > d + tau(d)         occluded: no evidence either way
//   outside / no depth     no evidence
// with tau(d) = registration_tolerance_m + depth_noise_sigmas * sigma(d), sigma the DepthModel's
// axial noise; depth outside the DepthModel's range is no reading.
// A correct transform makes most of the overlap agree and leaves almost nothing in free space;
// a wrong one that happens to align one plane (a textured floor) puts the rest of the scene in
// front of the other camera's surfaces. Correspondence counts are evidence, not the decision.
//
// Depends on Eigen and OpenCV core only (the views' depth images).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// A sampled depth pixel of a scan: its point and surface normal in the scan frame.
struct SurfacePoint {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;  // zero when the neighbourhood gave none
  float gray = -1.0f;      // grey level (0-255) of the sample's colour pixel; -1 = no colour
};

// Every config.pixel_stride-th valid depth pixel of every view of `scan`, off depth edges, with a
// normal: the samples one scan contributes to every check it is in (computed once per scan by
// Pipeline::Prepare, not once per candidate).
std::vector<SurfacePoint> SampleSurface(const Scan& scan, const VerifyConfig& config,
                                        const DepthModel& depth);

// Renders both scans into each other under T_target_source (see the file comment), runs the
// degeneracy probe and applies the thresholds of VerifyConfig (types.hpp documents the fields).
// The samples are SampleSurface of each scan with the same config.
VerificationResult VerifyRegistration(const Scan& source,
                                      const std::vector<SurfacePoint>& source_samples,
                                      const Scan& target,
                                      const std::vector<SurfacePoint>& target_samples,
                                      const Transform& T_target_source, const VerifyConfig& config,
                                      const DepthModel& depth);
// The same, sampling both scans first.
VerificationResult VerifyRegistration(const Scan& source, const Scan& target,
                                      const Transform& T_target_source, const VerifyConfig& config,
                                      const DepthModel& depth);

// What one source sample says in one target view, for the verification picture.
struct VerificationSample {
  float x = 0, y = 0;  // pixel of target view `view` where the sample lands
  enum Kind { kAgree, kViolate, kOccluded } kind = kAgree;
};
// The source samples (every VerifyConfig::pixel_stride-th depth pixel) that land in target view
// `view` under T_target_source with some evidence, in sampling order.
std::vector<VerificationSample> VerificationSamples(const Scan& source, const Scan& target,
                                                    const Transform& T_target_source,
                                                    const VerifyConfig& config,
                                                    const DepthModel& depth, int view);

}  // namespace zeroreg
