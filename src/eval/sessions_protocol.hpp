// The protocol of ../shared/sessions/README.md: recording B's poses given in a frame of its own
// (a seeded rigid "unalignment"), odometry drifted from the ground truth (seeded), and the errors
// of a merge against the truth, and the file that lists the splits (sessions.tsv). Eigen only.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

// One line of sessions.tsv: a scene of the data folder split into recordings A and B, inclusive
// ranges of the scene's frame ids.
struct SessionSplit {
  std::string scene;
  int a_first = 0, a_last = 0, b_first = 0, b_last = 0;
};

// Reads "scene<TAB>A<TAB>B" lines, A and B as FIRST-LAST; empty lines, '#' lines and the header
// line (starting with "scene") are skipped. Throws InputError naming the file (and line) when it
// cannot be read, a line is malformed, or it lists no split.
std::vector<SessionSplit> ReadSessionSplits(const std::string& path);

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
