// Where to render the target from so that it looks like the source's image: the source camera as
// each pose hypothesis places it in the target frame, or, with no hypothesis worth rendering from,
// the target's own cameras swung about the vertical through the surface they look at.
#pragma once

#include <string>
#include <vector>

#include "zeroreg/types.hpp"

namespace zeroreg {

struct VirtualCamera {
  std::string from;     // what placed it: a candidate's name, or "orbit +30 deg"
  int source_view = 0;  // the source view whose image is matched against the rendering
  Transform T_target_camera = Transform::Identity();  // virtual camera -> target scan frame
};

// A pose hypothesis T_target_source and the name of the candidate that proposed it.
struct PoseHypothesis {
  std::string name;
  Transform T_target_source = Transform::Identity();
};

// Whether two cameras are closer than `deg` and `m` (rotation angle, centre distance).
bool NearCamera(const Transform& a, const Transform& b, double deg, double m);

// For each hypothesis in order and each source view, the camera T_target_source T_scan_camera;
// a camera near one already kept (NearCamera with merge_deg, merge_m) is dropped, and at most
// max_cameras are returned (0 = no limit).
std::vector<VirtualCamera> CamerasFromHypotheses(const std::vector<PoseHypothesis>& hypotheses,
                                                 const Scan& source, double merge_deg,
                                                 double merge_m, int max_cameras);

// The fixed set: each target view's camera turned by each of `angles_deg` about the vertical axis
// (the camera's image-up direction; a handheld or head-worn camera is held roughly upright)
// through the centroid of the surface it sees, so that it looks at the same surface from the
// side. Matched against source view `source_view`.
std::vector<VirtualCamera> OrbitCameras(const Scan& target, const std::vector<double>& angles_deg,
                                        int source_view);

// The centroid of the surface a view sees, in the scan frame (every 8th depth pixel in
// [min_m, max_m]); the camera centre when it sees none.
Eigen::Vector3d SurfaceCentroid(const View& view, double min_m, double max_m);

}  // namespace zeroreg
