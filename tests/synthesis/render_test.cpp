// The renderer against synthetic depth grids with exact poses: a rendered view reproduces the
// depth, colour and 3D points a camera at that pose would see; holes stay holes; the z-buffer
// keeps the nearest surface; depth edges are not bridged.
#include "synthesis/render.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace zeroreg {
namespace {

constexpr int kWidth = 80, kHeight = 60;

Intrinsics TestIntrinsics() { return {100.0, 100.0, 39.5, 29.5, kWidth, kHeight}; }

// A colour that differs at every pixel, so a shifted rendering cannot pass by chance.
cv::Vec3b Texture(int u, int v) {
  return cv::Vec3b(static_cast<uchar>((u * 3) % 256), static_cast<uchar>((v * 4) % 256),
                   static_cast<uchar>((u * 7 + v * 11) % 256));
}

// A fronto-parallel plane at `depth_m` seen by a camera at the scan origin.
View PlaneView(float depth_m) {
  View view;
  view.intrinsics = TestIntrinsics();
  view.depth = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(depth_m));
  view.color = cv::Mat(kHeight, kWidth, CV_8UC3);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) view.color.at<cv::Vec3b>(v, u) = Texture(u, v);
  }
  return view;
}

Scan OneView(const View& view) {
  Scan scan;
  scan.views.push_back(view);
  return scan;
}

Transform Translation(double x, double y, double z) {
  Transform T = Transform::Identity();
  T.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return T;
}

TEST(Render, FromItsOwnCameraReproducesDepthColourAndPoints) {
  const View view = PlaneView(2.0f);
  const RenderedView r = RenderScan(OneView(view), Transform::Identity(), view.intrinsics);
  EXPECT_EQ(r.covered, kWidth * kHeight);
  const Intrinsics K = view.intrinsics;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      ASSERT_NEAR(r.depth.at<float>(v, u), 2.0f, 1e-5f) << u << "," << v;
      ASSERT_EQ(r.color.at<cv::Vec3b>(v, u), Texture(u, v)) << u << "," << v;
      const cv::Vec3f p = r.points.at<cv::Vec3f>(v, u);
      ASSERT_NEAR(p[0], (u - K.cx) / K.fx * 2.0, 1e-5);
      ASSERT_NEAR(p[1], (v - K.cy) / K.fy * 2.0, 1e-5);
      ASSERT_NEAR(p[2], 2.0, 1e-5);
    }
  }
}

TEST(Render, MovedCameraSeesTheShiftedImageAndAHoleWhereNothingWasSeen) {
  // 10 cm to the right at 2 m with f = 100 px: the image moves 5 px to the left.
  const View view = PlaneView(2.0f);
  const RenderedView r = RenderScan(OneView(view), Translation(0.1, 0, 0), view.intrinsics);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      if (u + 5 < kWidth) {
        ASSERT_NEAR(r.depth.at<float>(v, u), 2.0f, 1e-5f) << u << "," << v;
        ASSERT_EQ(r.color.at<cv::Vec3b>(v, u), Texture(u + 5, v)) << u << "," << v;
        ASSERT_NEAR(r.points.at<cv::Vec3f>(v, u)[0], (u + 5 - view.intrinsics.cx) / 100.0 * 2.0,
                    1e-5);
      } else {
        ASSERT_EQ(r.depth.at<float>(v, u), 0.0f) << u << "," << v;
        ASSERT_EQ(r.color.at<cv::Vec3b>(v, u), cv::Vec3b(0, 0, 0));
      }
    }
  }
  EXPECT_EQ(r.covered, (kWidth - 5) * kHeight);
}

TEST(Render, TurnedCameraSeesThePlaneAtTheDepthOfItsRays) {
  const View view = PlaneView(2.0f);
  // Turned 15 deg about the vertical axis, 20 cm back and 10 cm up.
  Transform T_scan_virtual = Translation(0.05, -0.1, -0.2);
  T_scan_virtual.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(15.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const RenderedView r = RenderScan(OneView(view), T_scan_virtual, view.intrinsics);
  const Intrinsics K = view.intrinsics;
  const Eigen::Matrix3d R = T_scan_virtual.topLeftCorner<3, 3>();
  const Eigen::Vector3d o = T_scan_virtual.topRightCorner<3, 1>();
  int checked = 0;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      // The ray of pixel (u, v) meets the plane z = 2 of the scan at depth lambda along the
      // virtual camera's z (the ray's z component there is 1).
      const Eigen::Vector3d ray = R * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
      const double lambda = (2.0 - o.z()) / ray.z();
      const Eigen::Vector3d hit = o + lambda * ray;
      const double su = K.fx * hit.x() / 2.0 + K.cx, sv = K.fy * hit.y() / 2.0 + K.cy;
      const bool inside = su > 1 && su < kWidth - 2 && sv > 1 && sv < kHeight - 2;
      const float depth = r.depth.at<float>(v, u);
      if (!inside) {
        if (su < -1 || su > kWidth || sv < -1 || sv > kHeight) {
          ASSERT_EQ(depth, 0.0f) << u << "," << v;
        }
        continue;
      }
      ASSERT_NEAR(depth, lambda, 1e-4) << u << "," << v;
      const cv::Vec3f p = r.points.at<cv::Vec3f>(v, u);
      ASSERT_NEAR((Eigen::Vector3d(p[0], p[1], p[2]) - hit).norm(), 0.0, 1e-4);
      ++checked;
    }
  }
  EXPECT_GT(checked, kWidth * kHeight / 3);
}

TEST(Render, HolesStayHolesAndThinHolesAreFilled) {
  View view = PlaneView(2.0f);
  view.depth(cv::Rect(20, 20, 12, 10)).setTo(0.0f);  // a hole much wider than fill_hole_px
  view.depth.col(60).setTo(0.0f);                    // a one-pixel crack
  const RenderedView r = RenderScan(OneView(view), Transform::Identity(), view.intrinsics);
  for (int v = 20; v < 30; ++v) {
    for (int u = 20; u < 32; ++u) {
      ASSERT_EQ(r.depth.at<float>(v, u), 0.0f) << u << "," << v;
      ASSERT_EQ(r.color.at<cv::Vec3b>(v, u), cv::Vec3b(0, 0, 0));
    }
  }
  for (int v = 0; v < kHeight; ++v) ASSERT_NEAR(r.depth.at<float>(v, 60), 2.0f, 1e-5f);
  EXPECT_EQ(r.covered, kWidth * kHeight - 12 * 10);

  RenderConfig no_fill;
  no_fill.fill_hole_px = 0;
  const RenderedView open =
      RenderScan(OneView(view), Transform::Identity(), view.intrinsics, no_fill);
  for (int v = 0; v < kHeight; ++v) ASSERT_EQ(open.depth.at<float>(v, 60), 0.0f);
}

TEST(Render, TheZBufferKeepsTheNearestSurfaceWhateverTheViewOrder) {
  View far = PlaneView(3.0f);
  View near = PlaneView(1.0f);
  near.color.setTo(cv::Scalar(10, 200, 30));
  near.depth.setTo(0.0f);
  near.depth(cv::Rect(30, 20, 20, 20)).setTo(1.0f);
  for (const bool near_first : {false, true}) {
    Scan scan;
    scan.views = near_first ? std::vector<View>{near, far} : std::vector<View>{far, near};
    const RenderedView r = RenderScan(scan, Transform::Identity(), far.intrinsics);
    for (int v = 0; v < kHeight; ++v) {
      for (int u = 0; u < kWidth; ++u) {
        const bool in_near = u >= 30 && u < 50 && v >= 20 && v < 40;
        ASSERT_NEAR(r.depth.at<float>(v, u), in_near ? 1.0f : 3.0f, 1e-5f) << u << "," << v;
        if (in_near) {
          ASSERT_EQ(r.color.at<cv::Vec3b>(v, u), cv::Vec3b(10, 200, 30));
        }
      }
    }
  }
}

TEST(Render, DepthEdgesAreNotBridged) {
  // Left half 1 m, right half 3 m: a camera moved 10 cm right sees past the edge onto far surface
  // the view never saw, and there is no mesh wall at intermediate depth, only a hole.
  View view = PlaneView(3.0f);
  view.depth(cv::Rect(0, 0, 40, kHeight)).setTo(1.0f);
  const RenderedView r = RenderScan(OneView(view), Translation(0.1, 0, 0), view.intrinsics);
  int holes = 0;
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const float d = r.depth.at<float>(v, u);
      if (d == 0.0f) {
        ++holes;
        continue;
      }
      ASSERT_TRUE(std::abs(d - 1.0f) < 1e-4f || std::abs(d - 3.0f) < 1e-4f) << u << "," << v;
    }
  }
  // The near half moves 10 px left (columns up to 29), the far one 3.3 px (36.7 to 75.7): 7
  // columns open up between them, and 4 at the right border nothing was seen in.
  EXPECT_EQ(holes, 11 * kHeight);
}

}  // namespace
}  // namespace zeroreg
