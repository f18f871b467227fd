#include "pipeline/input_checks.hpp"

#include <cmath>
#include <sstream>

#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {

// The core trusts its inputs; this is the boundary check for scans built by callers (C++ or
// Python), with messages that name the scan and view.
void CheckScan(const Scan& scan, const std::string& role) {
  const std::string where = role + " scan '" + scan.name + "'";
  if (scan.views.empty()) {
    throw MakeInputError(where, "has no views; expected at least one posed RGB-D view");
  }
  for (size_t i = 0; i < scan.views.size(); ++i) {
    const View& v = scan.views[i];
    const std::string view_where = where + " view " + std::to_string(i) + " (" + v.name + ")";
    if (v.color.empty() || v.color.type() != CV_8UC3) {
      throw MakeInputError(view_where, "colour image is empty or not 8-bit 3-channel");
    }
    if (v.depth.empty() || v.depth.type() != CV_32FC1) {
      throw MakeInputError(view_where, "depth image is empty or not float32 metres");
    }
    if (v.color.size() != v.depth.size()) {
      std::ostringstream s;
      s << "colour is " << v.color.cols << "x" << v.color.rows << " but depth is " << v.depth.cols
        << "x" << v.depth.rows << "; expected the same size";
      throw MakeInputError(view_where, s.str());
    }
    if (!(v.intrinsics.fx > 0 && v.intrinsics.fy > 0)) {
      throw MakeInputError(view_where, "intrinsics fx/fy must be positive");
    }
  }
}

// A prior that is not a rigid transform, or a tolerance that is not a positive number, is refused
// by name (InputError) rather than silently making every result invalid.
void CheckPrior(const std::optional<MotionPrior>& prior) {
  if (!prior) return;
  // The same test (and tolerances) as every pose file (ReadPoseFile): what reads as a pose is
  // accepted as a prior.
  detail::CheckRigid(prior->T_target_source, "motion prior T_target_source");
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(prior->max_rotation_deg) || !positive(prior->max_translation_m)) {
    std::ostringstream given;
    given << "max_rotation_deg " << prior->max_rotation_deg << ", max_translation_m "
          << prior->max_translation_m;
    throw MakeInputError("motion prior tolerance",
                         given.str() + ": expected positive numbers (degrees, metres)");
  }
}

}  // namespace zeroreg
