// The working scale of a registration (docs/CONFIG.md, "Any scale"). Every length of the config
// (RANSAC's inlier distance, ICP's gates and voxels, the check's tolerances, the object and FPFH
// voxels, the depth range, ...) was set and measured on rooms seen from 0.5-5 m. A scene seen
// from 20 cm (a phone at arm's length) or from 20 m is the same registration problem with every
// length multiplied by the ratio of the working distances. So the pipeline measures how far the
// cameras saw (the median of the valid depth readings) and, where that lies outside the range of
// working distances the defaults were measured on (ScaleConfig), works on the scans in units of
// k metres: depth, points and view poses divided by k, every setting read as it is written, the
// result's lengths multiplied by k again. Inside that range k = 1 exactly and nothing changes.
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
