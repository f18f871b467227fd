// What the commands over whole recordings share beside the stages themselves: the wall time and
// peak memory of each stage, and the placement of every frame by its keyframe's move.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "zeroreg/recordings.hpp"

namespace zeroreg {

// Peak resident memory of the process (VmHWM, MiB), and its reset (Linux: clear_refs 5), so each
// stage reports its own peak.
void ResetPeakRss();
double PeakRssMib();

// Appends {name, seconds, peak RSS} to `out` when it goes out of scope.
class StageClock {
 public:
  StageClock(std::string name, std::vector<StageReport>* out);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

 private:
  std::string name_;
  std::vector<StageReport>* out_;
  double start_s_;
};

// Every frame with a pose (`poses`, the recording's own frame), moved as its nearest keyframe at
// or before it (the first keyframe for frames before it) was moved: T_after * T_before^-1 of
// that keyframe of `recording`. Without poses, the keyframes' T_after. Empty when the recording
// has no keyframe.
std::map<int, Transform> PlacedTrajectory(const std::map<int, Transform>& poses,
                                          const std::vector<RecordingKeyframe>& keyframes,
                                          int recording);

}  // namespace zeroreg
