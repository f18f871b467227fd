// The working scale of a registration (docs/CONFIG.md, "Any scale"). Every length of the config
// (RANSAC's inlier distance, ICP's gates and voxels, the check's tolerances, the object and FPFH
// voxels, the depth range, ...) was set and measured on rooms seen from 0.5-5 m. A scene seen
// from 20 cm (a phone at arm's length) or from 20 m is the same registration problem with every
// length multiplied by the ratio of the working distances. So the pipeline reads the scale from
// the depth (ScaleConfig): from its noise where the depth is structured light, whose noise in
// inverse depth is a constant of the sensor (exactly the scale of a copy of the scenes the
// defaults were measured on), else from how far the cameras saw (the median valid depth) where
// that lies outside the range of working distances the defaults were measured on. It works on
// the scans in units of k metres: depth, points and view poses divided by k, every setting read
// as it is written, the result's lengths multiplied by k again. On the shipped scenes k = 1
// exactly and nothing changes.
#pragma once

#include <optional>

#include "zeroreg/config.hpp"
#include "zeroreg/register.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

// The median valid depth reading of the scan's views (metres), sampled on each view's pixel grid
// (src/estimate/lift.hpp, PixelGrid); nullopt when the scan has no view with valid depth (a bare
// point cloud).
std::optional<double> WorkingDistance(const Scan& scan);

// What a scan or pair says about its scale: how far the cameras saw and how noisy their depth
// was (a of sigma(d) = a d^2, metres at 1 m: src/estimate/depth_noise.hpp).
struct ScaleEvidence {
  std::optional<double> distance_m;
  std::optional<double> noise_at_1m_m;
};

// The scan's working distance and depth noise (the median over its views of each).
ScaleEvidence MeasureScale(const Scan& scan);

// A pair's: the geometric mean of the two scans' (or the one that is known), of each.
ScaleEvidence PairScale(const ScaleEvidence& source, const ScaleEvidence& target);

// k for a scan or pair (ScaleConfig): where its relative noise a d lies within what the
// structured-light frames the defaults were measured on span, sqrt(noise_min * noise_max) / a in
// quarter octaves (1 on those frames: their a lies within one eighth octave of it); else the
// working scale of the distance alone (below). scale.working_distance_m > 0 decides alone.
double WorkingScale(const ScaleEvidence& evidence, const ScaleConfig& config);

// Whether WorkingScale reads k from the depth noise (structured light) rather than the distance.
bool ScaleFromNoise(const ScaleEvidence& evidence, const ScaleConfig& config);

// k for a working distance: 1 inside [room_min_m, room_max_m] (and when the distance is unknown
// or scale.automatic is off), else distance / room_min_m below the range and distance /
// room_max_m above it, rounded to the nearest quarter octave (2^(n/4)): scans of one sequence
// then mostly share one k (and their prepared data), and k never differs from the exact ratio by
// more than 9 %. scale.working_distance_m > 0 replaces the measured distance.
double WorkingScale(std::optional<double> distance_m, const ScaleConfig& config);

// The working distance of a pair: the geometric mean of the two scans' (or the one that is
// known).
std::optional<double> PairWorkingDistance(std::optional<double> source_m,
                                          std::optional<double> target_m);

// The scan with every length divided by k: depth readings, points, the views' pose translations
// and the ground truth's. k = 1 returns an exact copy.
Scan InWorkingUnits(const Scan& scan, double k);

// A result made in working units of k metres, in metres: every transform's translation (the
// result's, the candidates', the alternatives', the rendered view's) and every length multiplied
// by k; the reason's prose keeps the working units and says so.
void ResultInMetres(double k, const std::optional<MotionPrior>& prior, RegistrationResult* r);

// The prior in working units of k metres.
std::optional<MotionPrior> PriorInWorkingUnits(const std::optional<MotionPrior>& prior, double k);

}  // namespace zeroreg
