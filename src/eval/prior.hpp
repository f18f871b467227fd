// A simulated motion prior for `zeroreg eval --prior-error-deg/--prior-error-m`: the ground truth
// moved by a fixed error, as odometry, an IMU or a SLAM front end would give it. A loop-closure
// user registers with such a prior (zeroreg::MotionPrior), and in symmetric scenes only the prior
// tells the true pose from a flipped one that the scans agree with as well (BENCHMARKS.md
// "Pairs that share nothing, or little"); this measures what a prior of a given quality buys on
// any pair list.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "zeroreg/register.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

struct PriorError {
  double rotation_deg = 0.0;   // the prior is turned this far from the truth (random axis)
  double translation_m = 0.0;  // and moved this far (random direction)
  // MotionPrior's tolerance: how far a valid pose may be from the prior (its defaults).
  double max_rotation_deg = MotionPrior().max_rotation_deg;
  double max_translation_m = MotionPrior().max_translation_m;
};
nlohmann::json PriorErrorToJson(const PriorError& error);

// T_gt moved by error.rotation_deg about a random axis and error.translation_m along a random
// direction, both applied in the source frame (T_gt * offset, as scripts/bench_common.py's
// pose_off_by): inv(T_gt) * prior turns by exactly rotation_deg and moves by exactly
// translation_m. The axis and the direction are drawn uniformly on the sphere from a generator
// seeded by `seed` and `pair_key`, so a pair gets the same prior in every run, with any --jobs or
// --shard. The draws are the same on any platform (std::mt19937_64 is fully specified and the
// doubles are made from its bits here, not by a library distribution); the prior itself to the
// last bit of the C library's sin and cos.
MotionPrior PriorOffTheTruth(const Transform& T_gt, const PriorError& error, std::uint64_t seed,
                             const std::string& pair_key);

}  // namespace zeroreg
