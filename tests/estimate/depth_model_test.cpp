// One DepthModel for every stage (include/zeroreg/config.hpp): lifting, the check's samples and
// tolerance, view synthesis and ICP all read the same range, edge rule and noise.
#include <gtest/gtest.h>

#include "estimate/icp.hpp"
#include "estimate/lift.hpp"
#include "noisy_wall.hpp"
#include "synthesis/render.hpp"
#include "verify/verify.hpp"

namespace zeroreg {
namespace {

// The noise-free wall of noisy_wall.hpp: 1.5 m deep at the left edge, 3 m at the right, a box
// 0.5 m in front of it in the lower middle.
Scan WallScan() {
  Scan scan;
  scan.views.push_back(testing::NoisyWall(0.0, 1));
  return scan;
}

int LiftedColumns(const View& view, const ViewLift& how) {
  int n = 0;
  for (int x = 0; x < 640; x += 8) n += LiftPixel(view, Eigen::Vector2f(x, 100.0f), how) ? 1 : 0;
  return n;
}

TEST(DepthModel, EveryStageDropsReadingsOutsideTheOneRange) {
  const Scan scan = WallScan();
  const View& view = scan.views[0];
  DepthModel near_only;
  near_only.max_m = 1.6;  // the wall's left eighth and part of the box

  const int lifted_all = LiftedColumns(view, LiftForView(LiftConfig(), DepthModel(), 0.0));
  const int lifted_near = LiftedColumns(view, LiftForView(LiftConfig(), near_only, 0.0));
  EXPECT_EQ(lifted_all, 80);
  EXPECT_GT(lifted_near, 0);
  EXPECT_LT(lifted_near, lifted_all / 2);

  for (const SurfacePoint& s : SampleSurface(scan, VerifyConfig(), near_only)) {
    EXPECT_LE(s.point.z(), near_only.max_m);
  }
  EXPECT_LT(SampleSurface(scan, VerifyConfig(), near_only).size(),
            SampleSurface(scan, VerifyConfig(), DepthModel()).size() / 2);

  RenderConfig render;
  render.depth = near_only;
  const RenderedView rendered = RenderScan(scan, Transform::Identity(), view.intrinsics, render);
  const RenderedView rendered_all = RenderScan(scan, Transform::Identity(), view.intrinsics);
  EXPECT_GT(rendered.covered, 0);
  EXPECT_LT(rendered.covered, rendered_all.covered / 2);
}

TEST(DepthModel, TheEdgeRuleIsShared) {
  // With an edge rule looser than the box's 0.5 m step (at most 33 % of the depth), its outline
  // is surface to lifting and to the check's samples alike.
  const Scan scan = WallScan();
  DepthModel loose;
  loose.edge_relative = 0.5;
  const Eigen::Vector2f on_the_box_edge(251.0f, 300.0f);
  EXPECT_FALSE(
      LiftPixel(scan.views[0], on_the_box_edge, LiftForView(LiftConfig(), DepthModel(), 0)));
  EXPECT_TRUE(LiftPixel(scan.views[0], on_the_box_edge, LiftForView(LiftConfig(), loose, 0)));
  EXPECT_GT(SampleSurface(scan, VerifyConfig(), loose).size(),
            SampleSurface(scan, VerifyConfig(), DepthModel()).size());
}

TEST(DepthModel, NoiseSetsTheCheckToleranceAndIcpWeights) {
  // A wall facing the camera 2 m away and a copy of it 5 cm behind: outside the check's
  // tolerance with Kinect noise (2 cm + 3 x 1.5 mm x 2^2 = 3.8 cm), inside it with ten times the
  // noise (20 cm).
  Scan scan = WallScan();
  scan.views[0].depth.setTo(2.0f);
  Transform behind = Transform::Identity();
  behind(2, 3) = 0.05;
  DepthModel noisy;
  noisy.noise_at_1m_m = 0.015;
  EXPECT_LT(VerifyRegistration(scan, scan, behind, VerifyConfig(), DepthModel()).overlap, 0.05);
  EXPECT_GT(VerifyRegistration(scan, scan, behind, VerifyConfig(), noisy).overlap, 0.9);

  for (const IcpStage& stage : IcpSchedule(RefineConfig(), noisy)) {
    EXPECT_EQ(stage.depth_noise_at_1m_m, noisy.noise_at_1m_m);
    EXPECT_EQ(stage.depth_noise_exponent, noisy.noise_exponent);
  }
}

}  // namespace
}  // namespace zeroreg
