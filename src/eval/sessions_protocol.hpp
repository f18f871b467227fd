// The protocol of ../shared/sessions/README.md: recording B's poses given in a frame of its own
// (a seeded rigid "unalignment"), odometry drifted from the ground truth (seeded), and the errors
// of a merge against the truth. Eigen only.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// T_Bframe_world: a uniform random rotation and a translation of uniform direction and length up
// to `max_translation_m`. Deterministic for a seed on every platform (raw bits of mt19937_64, no
// standard distribution).
Transform SeededUnalignment(std::uint64_t seed, double max_translation_m = 3.0);

// The ground truth's frame-to-frame motions (in frame-id order) each composed with an error of
// `translation_fraction` of its translation (random direction) and `rotation_deg` (random axis);
// the first pose is kept. Deterministic for a seed.
std::map<int, Transform> DriftedOdometry(const std::map<int, Transform>& ground_truth,
                                         std::uint64_t seed, double translation_fraction = 0.01,
                                         double rotation_deg = 0.1);

// Every pose of `poses` left-multiplied by T.
std::map<int, Transform> Moved(const Transform& T, const std::map<int, Transform>& poses);

// Absolute trajectory error: RMSE (metres) of the camera positions of the frames both have, with
// no alignment (both are in one frame). NaN when they share no frame.
double AbsoluteTrajectoryError(const std::map<int, Transform>& estimate,
                               const std::map<int, Transform>& ground_truth);

}  // namespace zeroreg
