// TUM trajectories (frame id as the time stamp) and recording specifications "DIR@FIRST-LAST".
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/recordings.hpp"

namespace zeroreg {

RecordingInput ParseRecordingSpec(const std::string& spec) {
  if (spec.empty()) throw InputError("recording: empty; expected DIR or DIR@FIRST-LAST");
  RecordingInput r;
  const std::size_t at = spec.rfind('@');
  r.root = spec.substr(0, at);
  if (at != std::string::npos) {
    const std::string range = spec.substr(at + 1);
    int first = 0, last = 0;
    char dash = 0, extra = 0;
    std::istringstream in(range);
    if (!(in >> first >> dash >> last) || dash != '-' || (in >> extra) || first < 0 ||
        last < first) {
      throw InputError(spec + ": '" + range +
                       "' is not a frame range; expected FIRST-LAST (frame ids, FIRST <= LAST)");
    }
    r.first_frame = first;
    r.last_frame = last;
  }
  if (r.root.empty()) throw InputError(spec + ": no folder before '@'; expected DIR@FIRST-LAST");
  return r;
}

std::map<int, Transform> GroundTruthPoses(const RecordingInput& recording) {
  DatasetOptions options;
  options.depth_scale = recording.depth_scale;
  const auto dataset = OpenDataset(recording.root, options);
  std::map<int, Transform> poses;
  for (int id : dataset->FrameIds()) {
    if (id < recording.first_frame) continue;
    if (recording.last_frame >= recording.first_frame && id > recording.last_frame) break;
    const View view = dataset->LoadFrame(id);
    if (view.T_world_camera_gt) poses[id] = *view.T_world_camera_gt;
  }
  return poses;
}

std::map<int, Transform> ReadTumTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw InputError(path + ": cannot read the trajectory (TUM format: id tx ty tz qx qy qz qw)");
  std::map<int, Transform> poses;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream fields(line);
    double id = 0, t[3], q[4];
    if (!(fields >> id >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3])) {
      throw InputError(path + ": line " + std::to_string(number) +
                       ": expected 8 numbers 'id tx ty tz qx qy qz qw'");
    }
    const Eigen::Quaterniond quaternion(q[3], q[0], q[1], q[2]);
    bool finite = std::isfinite(id);
    for (double v : t) finite = finite && std::isfinite(v);
    for (double v : q) finite = finite && std::isfinite(v);
    if (!finite || std::abs(quaternion.norm() - 1.0) > 1e-2 || id != std::floor(id) || id < 0) {
      throw InputError(path + ": line " + std::to_string(number) +
                       ": expected a non-negative integer frame id and a unit quaternion");
    }
    Transform T = Transform::Identity();
    T.topLeftCorner<3, 3>() = quaternion.normalized().toRotationMatrix();
    T.topRightCorner<3, 1>() = Eigen::Vector3d(t[0], t[1], t[2]);
    if (!poses.emplace(static_cast<int>(id), T).second) {
      throw InputError(path + ": line " + std::to_string(number) + ": frame " +
                       std::to_string(static_cast<int>(id)) + " is given twice");
    }
  }
  if (poses.empty()) throw InputError(path + ": no poses (TUM format: id tx ty tz qx qy qz qw)");
  return poses;
}

void WriteTumTrajectory(const std::string& path, const std::map<int, Transform>& poses) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot be written");
  out << "# frame_id tx ty tz qx qy qz qw (camera -> world, TUM order)\n";
  char buffer[320];
  for (const auto& [id, T] : poses) {
    Eigen::Quaterniond q(Eigen::Matrix3d(T.topLeftCorner<3, 3>()));
    q.normalize();
    std::snprintf(buffer, sizeof(buffer), "%d %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n", id,
                  T(0, 3), T(1, 3), T(2, 3), q.x(), q.y(), q.z(), q.w());
    out << buffer;
  }
  if (!out) throw InputError(path + ": write failed");
}

}  // namespace zeroreg
