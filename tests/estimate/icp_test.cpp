#include "estimate/icp.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "eval/metrics.hpp"

namespace zeroreg {
namespace {

// A room corner sampled every `step` metres: floor, two walls and two boxes on the floor, so
// that every rigid motion changes the geometry (no sliding direction).
std::vector<Eigen::Vector3d> RoomCorner(double step) {
  std::vector<Eigen::Vector3d> points;
  for (double a = 0; a <= 2.0; a += step) {
    for (double b = 0; b <= 2.0; b += step) {
      points.emplace_back(a, b, 0.0);  // floor
      points.emplace_back(a, 0.0, b);  // wall y = 0
      points.emplace_back(0.0, a, b);  // wall x = 0
    }
  }
  auto box = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& size) {
    for (double a = 0; a <= 1.0; a += step / size.maxCoeff()) {
      for (double b = 0; b <= 1.0; b += step / size.maxCoeff()) {
        for (int face = 0; face < 3; ++face) {
          Eigen::Vector3d p = lo;
          const int i = (face + 1) % 3, j = (face + 2) % 3;
          p[i] += a * size[i];
          p[j] += b * size[j];
          p[face] += size[face];  // the face away from the corner
          points.push_back(p);
        }
      }
    }
  };
  box({0.6, 0.9, 0.0}, {0.4, 0.3, 0.5});
  box({1.3, 0.4, 0.0}, {0.3, 0.5, 0.3});
  return points;
}

Transform Motion(double angle_deg, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  T.topRightCorner<3, 1>() = t;
  return T;
}

std::vector<Eigen::Vector3d> Moved(const std::vector<Eigen::Vector3d>& points, const Transform& T) {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : points) out.push_back((T * p.homogeneous()).head<3>());
  return out;
}

TEST(Icp, CoarseToFineRecoversAStartElevenCentimetresOff) {
  const std::vector<Eigen::Vector3d> target = RoomCorner(0.01);
  const Transform gt = Motion(4.0, {0.3, 1.0, 0.2}, {0.08, -0.05, 0.06});  // 11 cm, 4 deg
  // Depth-like noise on the source so that the fit is not trivially exact.
  std::vector<Eigen::Vector3d> source = Moved(target, gt.inverse());
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.003);
  for (Eigen::Vector3d& p : source) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));

  const IcpResult r = RefinePointToPlane(source, target, Transform::Identity(),
                                         IcpSchedule(RefineConfig(), DepthModel()));
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.003);
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 0.2);
  EXPECT_GT(r.fitness, 0.9);
  EXPECT_LT(r.rmse, 0.01);
}

TEST(Icp, ExactStartStaysPutAndDeterministic) {
  const std::vector<Eigen::Vector3d> target = RoomCorner(0.02);
  const Transform gt = Motion(10.0, {0.0, 0.0, 1.0}, {0.3, 0.1, 0.0});
  const std::vector<Eigen::Vector3d> source = Moved(target, gt.inverse());
  const IcpResult a =
      RefinePointToPlane(source, target, gt, IcpSchedule(RefineConfig(), DepthModel()));
  const IcpResult b =
      RefinePointToPlane(source, target, gt, IcpSchedule(RefineConfig(), DepthModel()));
  EXPECT_LT(TranslationErrorM(a.T_target_source, gt), 1e-4);
  EXPECT_TRUE((a.T_target_source.array() == b.T_target_source.array()).all());
}

TEST(Icp, ThreadCountDoesNotChangeOneBitAndPreparedGeometryIsReusable) {
  // 1 cm sampling: ~60k points, 2 cm voxels keep enough that the search is really split.
  const std::vector<Eigen::Vector3d> target = RoomCorner(0.01);
  const Transform gt = Motion(4.0, {0.3, 1.0, 0.2}, {0.08, -0.05, 0.06});
  std::vector<Eigen::Vector3d> source = Moved(target, gt.inverse());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.003);
  for (Eigen::Vector3d& p : source) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const std::vector<IcpStage> stages = IcpSchedule(RefineConfig(), DepthModel());
  const IcpGeometry source_geometry(source, stages), target_geometry(target, stages);
  ASSERT_GT(source_geometry.NumPoints(RefineConfig().voxel_m), 4096u);
  const IcpResult one = RefinePointToPlane(source_geometry, target_geometry, Transform::Identity(),
                                           stages, {}, /*threads=*/1);
  EXPECT_LT(TranslationErrorM(one.T_target_source, gt), 0.003);  // and it is right
  for (int threads : {2, 3, 8}) {
    const IcpResult many = RefinePointToPlane(source_geometry, target_geometry,
                                              Transform::Identity(), stages, {}, threads);
    EXPECT_TRUE((one.T_target_source.array() == many.T_target_source.array()).all()) << threads;
    EXPECT_EQ(one.iterations, many.iterations);
    EXPECT_EQ(one.fitness, many.fitness);
  }
  // The raw-point form builds the same geometry: the same bits.
  const IcpResult raw = RefinePointToPlane(source, target, Transform::Identity(), stages);
  EXPECT_TRUE((one.T_target_source.array() == raw.T_target_source.array()).all());
}

TEST(Icp, TooFewPointsReturnTheStartUnchanged) {
  const std::vector<Eigen::Vector3d> three = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  const Transform start = Motion(5.0, {1, 0, 0}, {0.1, 0, 0});
  const IcpResult r =
      RefinePointToPlane(three, three, start, IcpSchedule(RefineConfig(), DepthModel()));
  EXPECT_TRUE((r.T_target_source.array() == start.array()).all());
  EXPECT_EQ(r.iterations, 0);
}

// On a floor alone, point-to-plane ICP cannot see a start that is off along the floor,
// and whatever pulls it there (fringe pairs, noise) goes unchecked. The estimate's inlier
// correspondences anchor those motions: with them ICP lands on the truth, without them it keeps the
// in-plane error.
TEST(Icp, AnchorsFixWhatAPlaneLeavesOpen) {
  std::vector<Eigen::Vector3d> floor;
  for (double a = 0; a <= 3.0; a += 0.02) {
    for (double b = 0; b <= 3.0; b += 0.02) floor.emplace_back(a, b, 0.0);
  }
  const Transform gt = Motion(10, {0, 0, 1}, {0.3, -0.2, 0.0});  // a motion within the plane
  const std::vector<Eigen::Vector3d> target = Moved(floor, gt);
  const Transform start = Motion(1.5, {0, 0, 1}, {0.04, 0.03, 0.0}) * gt;  // 5 cm off in-plane
  IcpAnchors anchors;
  for (size_t k = 0; k < floor.size(); k += 997) {  // a few dozen textured floor matches
    anchors.source.push_back(floor[k]);
    anchors.target.push_back(target[k]);
  }
  ASSERT_GT(anchors.source.size(), 20u);
  const IcpResult plain =
      RefinePointToPlane(floor, target, start, IcpSchedule(RefineConfig(), DepthModel()));
  RefineConfig every_stage;  // what the pipeline does where the check flags degenerate geometry
  every_stage.anchor_weight_fine = every_stage.anchor_weight_coarse;
  const IcpResult anchored =
      RefinePointToPlane(floor, target, start, IcpSchedule(every_stage, DepthModel()), anchors);
  EXPECT_GT(TranslationErrorM(plain.T_target_source, gt), 0.03);  // plain ICP keeps the error
  EXPECT_LT(TranslationErrorM(anchored.T_target_source, gt), 0.005);
  EXPECT_LT(RotationErrorDeg(anchored.T_target_source, gt), 0.2);
}

// Depth-noise weights (RefineConfig::depth_noise_at_1m_m): a structured-light reading's error grows
// with the square of its depth, and far readings are also where a depth camera's calibration bias
// lives. A room corner 1-3 m from the camera in front of a wall 6 m away, whose readings in the
// source scan are 3 cm too deep (along the ray): unweighted ICP started at the truth is pulled off
// by the wall, the weighted fit trusts the near readings and stays.
TEST(Icp, DepthNoiseWeightsTrustNearReadingsOverABiasedFarWall) {
  std::vector<Eigen::Vector3d> target;  // camera frame of the target scan
  for (const Eigen::Vector3d& p : RoomCorner(0.02))
    target.push_back(p + Eigen::Vector3d(-1, -1, 1));
  for (double x = -3; x <= 3; x += 0.02) {
    for (double y = -3; y <= 3; y += 0.02) target.emplace_back(x, y, 6.0);
  }
  const Transform gt = Motion(5.0, {0.2, 1.0, 0.1}, {0.1, 0.0, -0.05});
  std::vector<Eigen::Vector3d> source = Moved(target, gt.inverse());
  std::vector<double> source_depth, target_depth;
  for (Eigen::Vector3d& p : source) {
    if (p.z() > 4.0) p += 0.03 * p.normalized();  // the far reading's bias
    source_depth.push_back(p.z());
  }
  for (const Eigen::Vector3d& p : target) target_depth.push_back(p.z());

  const DepthModel weighted;  // the default: 1.5 mm at 1 m, exponent 2
  ASSERT_GT(weighted.noise_at_1m_m, 0.0);
  DepthModel equal_weights;
  equal_weights.noise_at_1m_m = 0.0;
  const auto refine = [&](const DepthModel& depth, bool with_depth) {
    const std::vector<IcpStage> stages = IcpSchedule(RefineConfig(), depth);
    return RefinePointToPlane(
        IcpGeometry(source, stages, false, with_depth ? source_depth : std::vector<double>()),
        IcpGeometry(target, stages, true, with_depth ? target_depth : std::vector<double>()), gt,
        stages);
  };
  const IcpResult plain = refine(equal_weights, true);
  const IcpResult noise_weighted = refine(weighted, true);
  EXPECT_GT(TranslationErrorM(plain.T_target_source, gt), 0.01);
  EXPECT_LT(TranslationErrorM(noise_weighted.T_target_source, gt), 0.003);
  EXPECT_LT(RotationErrorDeg(noise_weighted.T_target_source, gt), 0.1);
  // Without depth readings (fused clouds) the weights are all equal: plain ICP, bit for bit.
  const IcpResult no_readings = refine(weighted, false);
  EXPECT_TRUE((no_readings.T_target_source.array() == plain.T_target_source.array()).all());
  // One reading per point or none.
  source_depth.pop_back();
  EXPECT_THROW(IcpGeometry(source, IcpSchedule(RefineConfig(), weighted), false, source_depth),
               std::invalid_argument);
}

}  // namespace
}  // namespace zeroreg
