// A second pose away from the reported one, for the arbiter's ambiguity test: the reported pose
// turned by a quarter, half or three-quarter turn about the target's vertical, through a centre
// on the surface it aligns, then ICP. A shape that looks the same after such a turn (a box seen
// from two opposite sides, a long table seen from both ends, an office whose walls repeat) gives a
// second pose the check accepts; a scene that does not, none.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "pipeline/sources/pose_source.hpp"

namespace zeroreg {
namespace {

// Centre of the source samples that T places on the target's first view's measured depth (within
// `tolerance_m`): the middle of what the two scans share. All placed samples when fewer than 20
// agree; nullopt without samples.
std::optional<Eigen::Vector3d> SharedCentre(const PairInputs& pair, const Transform& T,
                                            double tolerance_m, bool all) {
  const std::vector<SurfacePoint>& samples = pair.source.surface;
  if (samples.empty() || pair.target.scan.views.empty()) return std::nullopt;
  const View& view = pair.target.scan.views[0];
  const Transform camera_from_target = view.T_scan_camera.inverse();
  Eigen::Vector3d placed = Eigen::Vector3d::Zero(), shared = Eigen::Vector3d::Zero();
  int n_shared = 0;
  for (const SurfacePoint& s : samples) {
    const Eigen::Vector3d p = (T * s.point.homogeneous()).head<3>();
    placed += p;
    if (all) continue;
    const Eigen::Vector3d c = (camera_from_target * p.homogeneous()).head<3>();
    if (c.z() <= 0.1) continue;
    const int u =
        static_cast<int>(std::lround(view.intrinsics.fx * c.x() / c.z() + view.intrinsics.cx));
    const int v =
        static_cast<int>(std::lround(view.intrinsics.fy * c.y() / c.z() + view.intrinsics.cy));
    if (u < 0 || v < 0 || u >= view.depth.cols || v >= view.depth.rows) continue;
    const float d = view.depth.at<float>(v, u);
    if (d > 0 && std::abs(d - c.z()) < tolerance_m) {
      shared += p;
      ++n_shared;
    }
  }
  if (!all && n_shared >= 20) return Eigen::Vector3d(shared / n_shared);
  return Eigen::Vector3d(placed / static_cast<double>(samples.size()));
}

// The target's vertical. Hand-held and head-worn cameras are held about upright but pitched by
// up to tens of degrees (the TUM cabinet's camera looks down about 40 deg, so its image up is 40
// deg off gravity and a half turn about it lands 80 deg from the half turn about gravity). Rooms
// and furniture are bounded by horizontal and vertical planes, whose normals gather along three
// axes: the principal axes of the target surface's normals (eigenvectors of their scatter). An
// axis along which at least a tenth of the normals' weight lies (a plane the view sees, not an
// axis left arbitrary by a degenerate scatter) and within 45 deg of the image up (nearer to it
// than to the horizon) is the vertical, the nearest if several; otherwise the image up.
Eigen::Vector3d TargetVertical(const PairInputs& pair) {
  const Eigen::Vector3d up =
      -pair.target.scan.views[0].T_scan_camera.topLeftCorner<3, 3>().col(1).normalized();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  int n = 0;
  for (const SurfacePoint& s : pair.target.surface) {
    if (s.normal.squaredNorm() < 0.5) continue;
    scatter += s.normal * s.normal.transpose();
    ++n;
  }
  if (n == 0) return up;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d best = up;
  double best_cos = std::cos(45.0 * M_PI / 180.0);
  for (int k = 0; k < 3; ++k) {
    if (solver.eigenvalues()(k) < 0.1 * scatter.trace()) continue;
    const Eigen::Vector3d axis = solver.eigenvectors().col(k).normalized();
    const double c = std::abs(axis.dot(up));
    if (c > best_cos) {
      best_cos = c;
      best = axis.dot(up) < 0 ? Eigen::Vector3d(-axis) : axis;
    }
  }
  return best;
}

class TurnedPoseSource : public PoseSource {
 public:
  TurnedPoseSource(double degrees, bool about_all) : degrees_(degrees), about_all_(about_all) {}
  std::string name() const override {
    return "turned " + std::to_string(static_cast<int>(degrees_)) + (about_all_ ? " (all)" : "");
  }
  CostClass cost() const override { return CostClass::kSecondPose; }
  unsigned needs() const override { return kNeedsDepth; }
  std::optional<Proposal> Propose(PairInputs& pair, std::string* /*note*/) const override {
    if (pair.first == nullptr || !pair.config.verify.enabled) return std::nullopt;
    const Transform& T = pair.first->T_target_source;
    const std::optional<Eigen::Vector3d> centre =
        SharedCentre(pair, T, pair.config.ransac.inlier_threshold_m, about_all_);
    if (!centre) return std::nullopt;
    const Eigen::Vector3d up = TargetVertical(pair);
    Transform turn = Transform::Identity();
    turn.topLeftCorner<3, 3>() = Eigen::AngleAxisd(degrees_ * M_PI / 180.0, up).toRotationMatrix();
    turn.topRightCorner<3, 1>() = *centre - turn.topLeftCorner<3, 3>() * *centre;
    Proposal p;
    p.path = {degrees_ < 135   ? PathSource::kTurned90
              : degrees_ < 225 ? PathSource::kTurned180
                               : PathSource::kTurned270};
    p.pose = turn * T;
    // With a motion prior a start this far from it cannot end within its tolerance (ICP turns a
    // few degrees), so it could never rival a pose the prior accepts.
    if (pair.prior) {
      const PriorDistance d = DistanceFromPrior(*pair.prior, *p.pose);
      if (d.turned_deg > pair.prior->max_rotation_deg + 30.0) return std::nullopt;
    }
    p.effective = pair.method_effective != nullptr ? *pair.method_effective : pair.config;
    p.effective.verify.max_violation = pair.config.ambiguity.max_violation;
    return p;
  }

 private:
  double degrees_;
  bool about_all_;
};

}  // namespace

std::vector<std::unique_ptr<PoseSource>> MakeTurnedPoseSources() {
  std::vector<std::unique_ptr<PoseSource>> out;
  for (bool about_all : {false, true}) {
    for (double degrees : {90.0, 180.0, 270.0}) {
      out.push_back(std::make_unique<TurnedPoseSource>(degrees, about_all));
    }
  }
  return out;
}

}  // namespace zeroreg
