#include "viz/pictures.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

namespace zeroreg {
namespace {

namespace fs = std::filesystem;

// A scan of `views` flat grey views, each of its own shade so a picture shows which view it holds.
Scan GreyScan(const std::string& name, int views, int shade) {
  Scan scan;
  scan.name = name;
  for (int v = 0; v < views; ++v) {
    View view;
    view.name = name + " view " + std::to_string(v);
    view.color = cv::Mat(120, 160, CV_8UC3, cv::Scalar::all(shade + 20 * v));
    view.depth = cv::Mat(120, 160, CV_32F, cv::Scalar(1.5f));
    view.intrinsics = {150.0, 150.0, 80.0, 60.0};
    scan.views.push_back(view);
  }
  return scan;
}

Correspondence Match(int source_view, int target_view, float y) {
  Correspondence c;
  c.source_pixel = {20.0f, y};
  c.target_pixel = {60.0f, y};
  c.view = source_view;
  c.target_view = target_view;
  return c;
}

TEST(Pictures, CrossViewCorrespondencesGetTheirOwnPicture) {
  const Scan source = GreyScan("s", 2, 40), target = GreyScan("t", 2, 100);
  RegistrationResult result;
  result.correspondences = {Match(0, 0, 30), Match(0, 1, 50), Match(1, 0, 70)};
  result.is_inlier = {true, true, false};
  const fs::path dir = fs::path(::testing::TempDir()) / "zeroreg-pictures-cross";
  fs::remove_all(dir);
  const std::vector<std::string> written =
      WriteRegistrationPictures(dir.string(), source, target, result);
  for (const char* name : {"correspondences-view0.png", "correspondences-view1.png",
                           "correspondences-view0-1.png", "correspondences-view1-0.png"}) {
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "correspondences-view1-1.png"));  // same-view pairs keep old names

  // Source view 0 with target view 1: the right half is target view 1 (shade 120), and only the
  // correspondence of that view pair is drawn (an inlier, green, at y = 50).
  const cv::Mat picture = DrawCorrespondences(source, target, result, 0, 1);
  ASSERT_EQ(picture.cols, 320);
  EXPECT_EQ(picture.at<cv::Vec3b>(10, 300), cv::Vec3b(120, 120, 120));
  const cv::Vec3b on_line = picture.at<cv::Vec3b>(50, 100);
  EXPECT_GT(on_line[1], 150);  // green channel of the inlier colour
  EXPECT_LT(on_line[2], 100);
  EXPECT_EQ(picture.at<cv::Vec3b>(30, 100), cv::Vec3b(40, 40, 40));  // view pair 0-0 not drawn
}

// The verification picture colours each source depth sample by what the check found: a source
// plane 0.5 m in front of the target's plane (identity transform) lies in the target camera's free
// space (red); the same plane registered onto it agrees (green).
TEST(Pictures, VerificationPictureShowsAgreementAndFreeSpace) {
  const Scan target = GreyScan("t", 1, 100);
  Scan near = GreyScan("s", 1, 40);
  near.views[0].depth.setTo(1.0f);
  RegistrationResult result;
  result.T_target_source = Transform::Identity();
  auto dominant = [](const cv::Mat& picture) {
    int red = 0, green = 0;
    for (int y = 0; y < picture.rows - 20; ++y) {  // above the caption
      for (int x = 0; x < picture.cols; ++x) {
        const cv::Vec3b c = picture.at<cv::Vec3b>(y, x);
        red += c[2] > 200 && c[1] < 80;
        green += c[1] > 180 && c[2] < 80;
      }
    }
    return std::make_pair(red, green);
  };
  const auto [red_near, green_near] =
      dominant(DrawVerification(near, target, result, VerifyConfig(), 0));
  EXPECT_GT(red_near, 100);
  EXPECT_EQ(green_near, 0);
  const auto [red_same, green_same] =
      dominant(DrawVerification(GreyScan("s", 1, 40), target, result, VerifyConfig(), 0));
  EXPECT_GT(green_same, 100);
  EXPECT_EQ(red_same, 0);
}

}  // namespace
}  // namespace zeroreg
