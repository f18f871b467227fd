#include "recordings/stage_clock.hpp"

#include <chrono>
#include <fstream>

#include "estimate/rigid_inverse.hpp"

namespace zeroreg {
namespace {

double NowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void ResetPeakRss() {
  std::ofstream clear("/proc/self/clear_refs");
  if (clear) clear << "5";
}

double PeakRssMib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

StageClock::StageClock(std::string name, std::vector<StageReport>* out)
    : name_(std::move(name)), out_(out), start_s_(NowSeconds()) {
  ResetPeakRss();
}

StageClock::~StageClock() { out_->push_back({name_, NowSeconds() - start_s_, PeakRssMib()}); }

std::map<int, Transform> PlacedTrajectory(const std::map<int, Transform>& poses,
                                          const std::vector<RecordingKeyframe>& keyframes,
                                          int recording) {
  std::map<int, Transform> correction;  // frame -> T_after * T_before^-1
  for (const RecordingKeyframe& k : keyframes) {
    if (k.recording == recording) correction[k.frame] = k.T_after * RigidInverse(k.T_before);
  }
  std::map<int, Transform> out;
  if (correction.empty()) return out;
  if (poses.empty()) {
    for (const RecordingKeyframe& k : keyframes) {
      if (k.recording == recording) out[k.frame] = k.T_after;
    }
    return out;
  }
  for (const auto& [id, T] : poses) {
    auto it = correction.upper_bound(id);
    if (it != correction.begin()) --it;
    out[id] = it->second * T;
  }
  return out;
}

}  // namespace zeroreg
