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

// A view-synthesis result: its correspondences' target pixels are in a rendering (target view
// -1), drawn in synthesized-view<i>.png beside the source image; no correspondence picture is
// asked of a target view that does not exist.
TEST(Pictures, SynthesizedViewShowsTheRenderingBesideTheSourceImage) {
  const Scan source = GreyScan("s", 1, 40), target = GreyScan("t", 1, 100);
  RegistrationResult result;
  result.correspondences = {Match(0, -1, 30), Match(0, -1, 50)};
  result.is_inlier = {true, false};
  result.rendered_view =
      RenderedCamera{0, Transform::Identity(), {150.0, 150.0, 80.0, 60.0, 160, 120}, "test"};
  const fs::path dir = fs::path(::testing::TempDir()) / "zeroreg-pictures-synthesized";
  fs::remove_all(dir);
  WriteRegistrationPictures(dir.string(), source, target, result);
  EXPECT_TRUE(fs::exists(dir / "synthesized-view0.png"));
  EXPECT_TRUE(IsRegistrationPictureName("synthesized-view0.png"));
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find("view0--1"), std::string::npos);
  }
  // Left the source image (shade 40), right the target rendered from its own camera (shade 100),
  // the inlier green across at y = 30, the outlier red at y = 50.
  const cv::Mat picture = DrawSynthesizedView(source, target, result);
  ASSERT_EQ(picture.cols, 320);
  EXPECT_EQ(picture.at<cv::Vec3b>(10, 10), cv::Vec3b(40, 40, 40));
  EXPECT_EQ(picture.at<cv::Vec3b>(10, 300), cv::Vec3b(100, 100, 100));
  EXPECT_GT(picture.at<cv::Vec3b>(30, 100)[1], 150);
  EXPECT_GT(picture.at<cv::Vec3b>(50, 100)[2], 150);
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
      dominant(DrawVerification(near, target, result, VerifyConfig(), DepthModel(), 0));
  EXPECT_GT(red_near, 100);
  EXPECT_EQ(green_near, 0);
  const auto [red_same, green_same] = dominant(
      DrawVerification(GreyScan("s", 1, 40), target, result, VerifyConfig(), DepthModel(), 0));
  EXPECT_GT(green_same, 100);
  EXPECT_EQ(red_same, 0);
}

TEST(Pictures, HypothesesShowTheChosenCandidateFirstThenTheRunnersUp) {
  const Scan source = GreyScan("s", 1, 40), target = GreyScan("t", 1, 100);
  RegistrationResult result;
  Transform shifted = Transform::Identity();
  shifted(0, 3) = 5.0;  // moves the source out of the target camera's view
  result.candidates = {{"object ransac", shifted, 0.1, false, false},
                       {"geometry clique icp", Transform::Identity(), 0.6, true, true},
                       {"image clique", shifted, 0.3, false, false}};
  const cv::Mat picture = DrawHypotheses(source, target, result, 0, 6);
  ASSERT_EQ(picture.cols, 2 * 160);  // two tiles a row
  ASSERT_EQ(picture.rows, 2 * 120);  // three candidates: two rows
  // Top left is the chosen identity: the source (orange) covers the flat target's pixels; the
  // candidates that moved the source away show the target alone (blue), and the fourth tile is
  // empty (white).
  const cv::Vec3b orange(30, 140, 250), blue(200, 120, 30), white(255, 255, 255);
  int orange_chosen = 0, orange_runner_up = 0, blue_runner_up = 0;
  for (int y = 10; y < 80; ++y) {
    for (int x = 10; x < 150; ++x) {
      orange_chosen += picture.at<cv::Vec3b>(y, x) == orange;
      orange_runner_up += picture.at<cv::Vec3b>(y, 160 + x) == orange;
      blue_runner_up += picture.at<cv::Vec3b>(y, 160 + x) == blue;
    }
  }
  EXPECT_GT(orange_chosen, 1000);
  EXPECT_EQ(orange_runner_up, 0);
  EXPECT_GT(blue_runner_up, 1000);
  EXPECT_EQ(picture.at<cv::Vec3b>(120 + 40, 160 + 80), white);
  // With a choice to show, WriteRegistrationPictures writes it.
  const fs::path dir = fs::path(::testing::TempDir()) / "zeroreg-pictures-hypotheses";
  fs::remove_all(dir);
  WriteRegistrationPictures(dir.string(), source, target, result);
  EXPECT_TRUE(fs::exists(dir / "hypotheses-view0.png"));
}

}  // namespace
}  // namespace zeroreg
