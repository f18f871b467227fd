// Which view pairs whole-image matching uses (method.whole_image_max_view_pairs):
// the overlap score finds the views that share a place, on synthetic descriptors
// where which views share one is known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "pipeline/image_correspondences.hpp"

namespace zeroreg {
namespace {

// A "place": unit descriptors of its surface points, as any view of it would see them.
Eigen::MatrixXf RandomUnitRows(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> normal;
  Eigen::MatrixXf g(n, 64);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 64; ++k) g(i, k) = normal(rng);
    g.row(i).normalize();
  }
  return g;
}

// A view of `shared` rows of `place` (noisy copies) plus distinct clutter of its own.
LiftedFeatures View(const Eigen::MatrixXf& place, int shared, int clutter, std::uint64_t seed) {
  const Eigen::MatrixXf noise = RandomUnitRows(shared + clutter, seed);
  LiftedFeatures v;
  v.features.descriptors.resize(shared + clutter, 64);
  for (int i = 0; i < shared; ++i) {
    v.features.descriptors.row(i) = (place.row(i) + 0.3f * noise.row(i)).normalized();
  }
  for (int i = shared; i < shared + clutter; ++i) v.features.descriptors.row(i) = noise.row(i);
  const int n = shared + clutter;
  v.features.keypoints.assign(static_cast<size_t>(n), Eigen::Vector2f::Zero());
  v.features.scores.assign(static_cast<size_t>(n), 1.0f);
  v.points.assign(static_cast<size_t>(n), Eigen::Vector3d::Zero());
  return v;
}

TEST(ViewOverlapScore, SharedSurfaceScoresFarAboveUnrelatedViews) {
  const Eigen::MatrixXf place = RandomUnitRows(400, 1);
  const LiftedFeatures a = View(place, 300, 500, 2), b = View(place, 300, 500, 3);
  const LiftedFeatures unrelated = View(RandomUnitRows(400, 4), 300, 500, 5);
  const int same = ViewOverlapScore(a, b), other = ViewOverlapScore(a, unrelated);
  EXPECT_GT(same, 200);  // most of the 300 shared points
  EXPECT_LT(other, 30);
  EXPECT_EQ(ViewOverlapScore(a, LiftedFeatures{}), 0);
}

TEST(ChooseViewPairs, KeepsTheOverlappingPairsInSourceMajorOrderWhateverTheThreads) {
  // Source views 0, 1, 2 see places A, B, C; target views 0, 1, 2 see C, D, A: only (0, 2) and
  // (2, 0) share a place.
  std::vector<Eigen::MatrixXf> places;
  for (int p = 0; p < 4; ++p) places.push_back(RandomUnitRows(300, 10 + p));
  const std::vector<LiftedFeatures> source = {
      View(places[0], 250, 300, 20), View(places[1], 250, 300, 21), View(places[2], 250, 300, 22)};
  const std::vector<LiftedFeatures> target = {
      View(places[2], 250, 300, 30), View(places[3], 250, 300, 31), View(places[0], 250, 300, 32)};
  const std::vector<std::pair<int, int>> expected = {{0, 2}, {2, 0}};
  for (const int threads : {1, 2, 5}) {
    EXPECT_EQ(ChooseViewPairs(source, target, {true, 2}, threads), expected);
  }
  // 0 = every pair; more allowed than there are = every pair; view i with view i only.
  EXPECT_EQ(ChooseViewPairs(source, target, {true, 0}, 2).size(), 9u);
  EXPECT_EQ(ChooseViewPairs(source, target, {true, 9}, 2).size(), 9u);
  const std::vector<std::pair<int, int>> diagonal = {{0, 0}, {1, 1}, {2, 2}};
  EXPECT_EQ(ChooseViewPairs(source, target, {false, 0}, 2), diagonal);
  // Three of nine (as many as the views, the default): the two sharing a place and one more.
  for (const int max_pairs : {3, WholeImageViewPairs::kAsManyAsViews}) {
    const std::vector<std::pair<int, int>> three =
        ChooseViewPairs(source, target, {true, max_pairs}, 2);
    ASSERT_EQ(three.size(), 3u);
    EXPECT_NE(std::find(three.begin(), three.end(), std::pair<int, int>{0, 2}), three.end());
    EXPECT_NE(std::find(three.begin(), three.end(), std::pair<int, int>{2, 0}), three.end());
  }
  // A frame pair has its one view pair whatever the setting.
  const std::vector<std::pair<int, int>> one = {{0, 0}};
  const std::vector<LiftedFeatures> frame_s = {source[0]}, frame_t = {target[1]};
  for (const int max_pairs : {0, 1, 3, WholeImageViewPairs::kAsManyAsViews}) {
    EXPECT_EQ(ChooseViewPairs(frame_s, frame_t, {true, max_pairs}, 2), one);
  }
}

}  // namespace
}  // namespace zeroreg
