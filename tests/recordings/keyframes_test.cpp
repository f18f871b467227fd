#include "recordings/keyframes.hpp"

#include <gtest/gtest.h>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// A 64x48 camera (f = 50 px, principal point on a pixel) facing a flat wall `wall_m` ahead. A
// camera moved sideways by 0.04 m sees the wall shifted by exactly 50 * 0.04 / 2 = 1 px when the
// wall is 2 m away, so n such steps share (64 - n) / 64 of the columns, exactly.
View Wall(double wall_m = 2.0) {
  View v;
  v.name = "wall";
  v.intrinsics = {50.0, 50.0, 32.0, 24.0, 64, 48};
  v.depth = cv::Mat(48, 64, CV_32FC1, cv::Scalar(static_cast<float>(wall_m)));
  return v;
}

Transform Sideways(double x_m) {
  Transform T = Transform::Identity();
  T(0, 3) = x_m;
  return T;
}

KeyframeConfig EveryPixel() {
  KeyframeConfig c;
  c.pixel_stride = 1;
  return c;
}

TEST(Keyframes, SeenFractionOfAShiftedWallIsTheSharedColumns) {
  const View a = Wall(), b = Wall();
  // b's camera 0.4 m to the right of a's: a's points move 10 px left in b; columns 0-9 leave.
  const Transform T_b_a = Sideways(0.4).inverse();
  EXPECT_DOUBLE_EQ(SeenFraction(a, b, T_b_a, EveryPixel()), 54.0 / 64.0);
  EXPECT_DOUBLE_EQ(Covisibility(a, Transform::Identity(), b, Sideways(0.4), EveryPixel()),
                   54.0 / 64.0);
  EXPECT_DOUBLE_EQ(SeenFraction(a, b, Transform::Identity(), EveryPixel()), 1.0);
}

TEST(Keyframes, DepthBeyondTheToleranceIsNotSeen) {
  // The same pixels, but b measures the wall 0.2 m farther than a's points land: no agreement
  // within 0.1 m; within 0.3 m, all of it.
  KeyframeConfig c = EveryPixel();
  EXPECT_DOUBLE_EQ(SeenFraction(Wall(2.0), Wall(2.2), Transform::Identity(), c), 0.0);
  c.depth_tolerance_m = 0.3;
  EXPECT_DOUBLE_EQ(SeenFraction(Wall(2.0), Wall(2.2), Transform::Identity(), c), 1.0);
}

TEST(Keyframes, CovisibilityIsTheSmallerDirection) {
  // a sees only the left half with depth: all of its points are on b's wall, but only half of
  // b's points land on a's measured depth.
  View a = Wall();
  a.depth.colRange(32, 64).setTo(0.0f);
  EXPECT_DOUBLE_EQ(SeenFraction(a, Wall(), Transform::Identity(), EveryPixel()), 1.0);
  EXPECT_DOUBLE_EQ(SeenFraction(Wall(), a, Transform::Identity(), EveryPixel()), 0.5);
  EXPECT_DOUBLE_EQ(
      Covisibility(a, Transform::Identity(), Wall(), Transform::Identity(), EveryPixel()), 0.5);
}

TEST(Keyframes, NewKeyframeWhenCovisibilityDropsBelowTheThreshold) {
  // 1 px per frame: frame n shares (64 - n) / 64 with frame 0, which is below 0.75 from n = 17
  // on; the next keyframe then counts from 17.
  KeyframeConfig c = EveryPixel();
  c.covisibility_threshold = 0.75;
  std::vector<View> frames;
  std::vector<std::optional<Transform>> poses;
  for (int i = 0; i < 40; ++i) {
    frames.push_back(Wall());
    poses.push_back(Sideways(0.04 * i));
  }
  EXPECT_EQ(SelectKeyframes(frames, poses, c), (std::vector<int>{0, 17, 34}));

  KeyframeSelector selector(c);
  ASSERT_TRUE(selector.Add(frames[0], poses[0]));
  EXPECT_FALSE(selector.last_covisibility().has_value());
  EXPECT_FALSE(selector.Add(frames[16], poses[16]));
  EXPECT_DOUBLE_EQ(*selector.last_covisibility(), 48.0 / 64.0);
  EXPECT_TRUE(selector.Add(frames[17], poses[17]));
  EXPECT_DOUBLE_EQ(*selector.last_covisibility(), 47.0 / 64.0);
}

TEST(Keyframes, AStillCameraMakesOneKeyframe) {
  std::vector<View> frames(30, Wall());
  std::vector<std::optional<Transform>> poses(30, Transform::Identity());
  EXPECT_EQ(SelectKeyframes(frames, poses), (std::vector<int>{0}));
}

TEST(Keyframes, WithoutPosesEveryKthFrame) {
  KeyframeConfig c;
  c.fallback_every = 3;
  std::vector<View> frames(10, Wall());
  EXPECT_EQ(SelectKeyframes(frames, {}, c), (std::vector<int>{0, 3, 6, 9}));
  // In a posed sequence, a frame without a pose is decided by the count of frames since the last
  // keyframe (frame 2: two frames, not yet; frame 5: five, so it is one); a posed frame after a
  // keyframe without a pose has nothing to be compared with and counts on (frame 8).
  std::vector<std::optional<Transform>> poses(10, Transform::Identity());
  poses[2] = std::nullopt;
  EXPECT_EQ(SelectKeyframes(frames, poses, c), (std::vector<int>{0}));
  poses[5] = std::nullopt;
  EXPECT_EQ(SelectKeyframes(frames, poses, c), (std::vector<int>{0, 5, 8}));
}

TEST(Keyframes, BadInputIsRefusedByName) {
  KeyframeConfig c;
  c.covisibility_threshold = 1.5;
  EXPECT_THROW(KeyframeSelector{c}, InputError);
  c = KeyframeConfig();
  c.fallback_every = 0;
  try {
    ValidateKeyframeConfig(c);
    FAIL() << "fallback_every = 0 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fallback_every"), std::string::npos) << e.what();
  }
  std::vector<View> frames(3, Wall());
  EXPECT_THROW(SelectKeyframes(frames, {Transform::Identity()}), InputError);
  View no_depth = Wall();
  no_depth.depth = cv::Mat();
  EXPECT_THROW(SeenFraction(no_depth, Wall(), Transform::Identity()), InputError);
}

}  // namespace
}  // namespace zeroreg
