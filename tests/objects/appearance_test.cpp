// Object appearance: the colour descriptor against colours with known answers,
// its mean over views, the appearance term of the node similarity C (exact values), and the
// appearance gate of the cross-view association.
#include "objects/appearance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "graph/scene_graph.hpp"
#include "objects/scene_objects.hpp"
#include "segment/segmenter.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

cv::Mat Solid(const cv::Scalar& bgr) { return cv::Mat(60, 80, CV_8UC3, bgr); }
cv::Mat FullMask() { return cv::Mat(60, 80, CV_8UC1, cv::Scalar(255)); }

double Norm(const Appearance& a) {
  double s = 0;
  for (float v : a.values) s += static_cast<double>(v) * v;
  return std::sqrt(s);
}

TEST(Appearance, ColourHistogramSeparatesHuesAndToleratesBrightness) {
  const Appearance red = ColourAppearance(Solid({30, 30, 200}), FullMask());
  const Appearance dark_red = ColourAppearance(Solid({15, 15, 110}), FullMask());
  const Appearance blue = ColourAppearance(Solid({200, 40, 30}), FullMask());
  const Appearance grey = ColourAppearance(Solid({128, 128, 128}), FullMask());
  ASSERT_FALSE(red.empty());
  EXPECT_EQ(red.kind, kColourHistogramKind);
  EXPECT_EQ(red.values.size(), 40u);
  EXPECT_NEAR(Norm(red), 1.0, 1e-6);
  // One bin each: the Bhattacharyya coefficient is 1 for the same bin, 0 for different ones.
  EXPECT_NEAR(AppearanceSimilarity(red, dark_red), 1.0, 1e-6);  // half the brightness, same hue
  EXPECT_NEAR(AppearanceSimilarity(red, blue), 0.0, 1e-6);
  EXPECT_NEAR(AppearanceSimilarity(red, grey), 0.0, 1e-6);

  // Half red, half blue against all red: BC = sqrt(0.5 * 1) = 0.707.
  cv::Mat mixed = Solid({30, 30, 200});
  mixed(cv::Rect(0, 0, 40, 60)).setTo(cv::Scalar(200, 40, 30));
  const Appearance half = ColourAppearance(mixed, FullMask());
  EXPECT_NEAR(AppearanceSimilarity(half, red), std::sqrt(0.5), 1e-6);

  // Only the masked pixels count.
  cv::Mat mask = cv::Mat::zeros(60, 80, CV_8UC1);
  mask(cv::Rect(45, 10, 20, 20)).setTo(255);
  EXPECT_NEAR(AppearanceSimilarity(ColourAppearance(mixed, mask), red), 1.0, 1e-6);
  EXPECT_TRUE(ColourAppearance(mixed, cv::Mat::zeros(60, 80, CV_8UC1)).empty());
  EXPECT_TRUE(ColourAppearance(mixed, cv::Mat::ones(10, 10, CV_8UC1)).empty());
}

TEST(Appearance, KindsAreNotComparedAndTheMeanIsUnitLength) {
  const Appearance red = ColourAppearance(Solid({30, 30, 200}), FullMask());
  const Appearance blue = ColourAppearance(Solid({200, 40, 30}), FullMask());
  Appearance other = red;
  other.kind = "sam-embedding";
  EXPECT_FALSE(Comparable(red, other));
  EXPECT_EQ(AppearanceSimilarity(red, other), 0.0);
  EXPECT_FALSE(Comparable(red, Appearance{}));

  const Appearance mean = MeanAppearance({&red, &blue, nullptr, &other});  // other: skipped
  EXPECT_EQ(mean.kind, kColourHistogramKind);
  EXPECT_NEAR(Norm(mean), 1.0, 1e-6);
  EXPECT_NEAR(AppearanceSimilarity(mean, red), std::sqrt(0.5), 1e-6);
  EXPECT_TRUE(MeanAppearance({}).empty());
}

// C_jk = 1 + cos(s_j, s_k) - lambda (1 - A_jk) where comparable; the paper's C where not.
TEST(Appearance, NodeSimilarityTermIsExact) {
  Eigen::MatrixXd s_p(2, 2), s_q(2, 2);
  s_p << 1, 0, 0, 1;
  s_q << 1, 0, 1, 0;  // both target objects share source object 0's label
  Eigen::MatrixXd A(2, 2), comparable(2, 2);
  A << 0.9, 0.2, 0.5, 0.4;
  comparable << 1, 1, 1, 0;
  const Eigen::MatrixXd plain = NodeSimilarity(s_p, s_q);
  EXPECT_TRUE(NodeSimilarity(s_p, s_q, A, comparable, 0.0).isApprox(plain));
  const Eigen::MatrixXd C = NodeSimilarity(s_p, s_q, A, comparable, 2.0);
  EXPECT_NEAR(C(0, 0), 2.0 - 2.0 * 0.1, 1e-12);
  EXPECT_NEAR(C(0, 1), 2.0 - 2.0 * 0.8, 1e-12);  // same label, other colours: the lookalike loses
  EXPECT_NEAR(C(1, 0), 1.0 - 2.0 * 0.5, 1e-12);
  EXPECT_NEAR(C(1, 1), 1.0, 1e-12);  // not comparable: no appearance term
  EXPECT_THROW(NodeSimilarity(s_p, s_q, A, comparable, -1.0), InputError);
  EXPECT_THROW(NodeSimilarity(s_p, s_q, A.topRows(1), comparable, 1.0), InputError);
}

std::vector<Eigen::Vector3d> Cube(const Eigen::Vector3d& lo, double edge) {
  std::vector<Eigen::Vector3d> p;
  for (double x = 0; x <= edge; x += 0.01)
    for (double y = 0; y <= edge; y += 0.01)
      for (double z = 0; z <= edge; z += 0.01) p.push_back(lo + Eigen::Vector3d(x, y, z));
  return p;
}

// Two chairs side by side, each seen in views 0 and 1; in view 1 the red chair's box also covers
// the blue chair's place (overlap), so label + overlap alone merge the wrong pair first.
TEST(Appearance, AssociationGateKeepsLookalikeObjectsApart) {
  const Appearance red = ColourAppearance(Solid({30, 30, 200}), FullMask());
  const Appearance blue = ColourAppearance(Solid({200, 40, 30}), FullMask());
  auto obs = [](int view, const std::vector<Eigen::Vector3d>& points, const Appearance& a) {
    ObjectObservation o;
    o.view = view;
    o.detection.label = "chair";
    o.detection.score = 0.5f;
    o.points = points;
    o.appearance = a;
    return o;
  };
  const auto blue_place = Cube({0.5, 0, 2}, 0.3);
  auto red_wide = Cube({0, 0, 2}, 0.3);
  const auto red_place = red_wide;
  red_wide.insert(red_wide.end(), blue_place.begin(), blue_place.end());
  const std::vector<ObjectObservation> observations = {
      obs(0, blue_place, blue), obs(1, red_wide, red), obs(0, red_place, red),
      obs(1, blue_place, blue)};
  ObjectsConfig config;
  // Without appearance: view-0 blue merges with view-1 red (they overlap), and the rest cannot.
  auto objects = AssociateObservations(observations, 2, config);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].observations, (std::vector<int>{0, 1}));
  // With the gate, each chair is associated with itself.
  config.association_min_appearance = 0.5;
  objects = AssociateObservations(observations, 2, config);
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].observations, (std::vector<int>{0, 3}));
  EXPECT_EQ(objects[1].observations, (std::vector<int>{1, 2}));
  EXPECT_NEAR(AppearanceSimilarity(objects[0].appearance, blue), 1.0, 1e-6);
  EXPECT_NEAR(AppearanceSimilarity(objects[1].appearance, red), 1.0, 1e-6);
}

// A 3-channel embedding on a 4 x 4 grid of 10 px cells under a 40 x 30 image: row 3 of the grid is
// padding below the image and must not count. Channel 0 = 1 in the left half, channel 1 = 1 in
// the top row, channel 2 = 2 everywhere (the common component that centring removes).
ImageEmbedding ToyEmbedding() {
  ImageEmbedding e;
  e.channels = 3;
  e.rows = e.cols = 4;
  e.pixels_per_cell = 10.0;
  e.data.assign(3 * 16, 0.0f);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const int cell = r * 4 + c;
      e.data[0 * 16 + cell] = r == 3 ? 1000.0f : (c < 2 ? 1.0f : 0.0f);
      e.data[1 * 16 + cell] = r == 3 ? 1000.0f : (r == 0 ? 1.0f : 0.0f);
      e.data[2 * 16 + cell] = r == 3 ? 1000.0f : 2.0f;
    }
  }
  return e;
}

TEST(Appearance, EmbeddingPooledOverTheMaskMinusTheViewMean) {
  const ImageEmbedding e = ToyEmbedding();
  const cv::Size size(40, 30);
  const EmbeddingPooler pooler(e, size);
  // View mean over the 12 image cells (100 px each): (0.5, 1/3, 2).
  cv::Mat top_left = cv::Mat::zeros(size, CV_8UC1);
  top_left(cv::Rect(0, 0, 10, 10)).setTo(255);  // cell (0, 0): (1, 1, 2) -> centred (0.5, 2/3, 0)
  const Appearance a = pooler.Pool(top_left);
  ASSERT_EQ(a.kind, kSamEmbeddingKind);
  ASSERT_EQ(a.values.size(), 3u);
  EXPECT_NEAR(a.values[0], 0.6, 1e-6);
  EXPECT_NEAR(a.values[1], 0.8, 1e-6);
  EXPECT_NEAR(a.values[2], 0.0, 1e-6);

  cv::Mat bottom_right = cv::Mat::zeros(size, CV_8UC1);  // cell (2, 3): (0, 0, 2)
  bottom_right(cv::Rect(30, 20, 10, 10)).setTo(255);
  const Appearance b = pooler.Pool(bottom_right);
  ASSERT_FALSE(b.empty());
  const double bn = std::sqrt(0.25 + 1.0 / 9.0);  // centred (-0.5, -1/3, 0)
  EXPECT_NEAR(b.values[0], -0.5 / bn, 1e-6);
  EXPECT_NEAR(b.values[1], -1.0 / 3.0 / bn, 1e-6);
  // The raw pooled vectors (1, 1, 2) and (0, 0, 2) have cosine 0.82; centred they point apart.
  EXPECT_LT(AppearanceSimilarity(a, b), 0.0);

  // Weights are pixels: 50 px in cell (0, 0) and 50 in cell (1, 3) pool to (0.5, 0.5, 2), centred
  // (0, 1/6, 0). Pixels are placed by their centres: x = 9 is in column 0, x = 10 in column 1.
  cv::Mat split = cv::Mat::zeros(size, CV_8UC1);
  split(cv::Rect(0, 0, 10, 5)).setTo(255);
  split(cv::Rect(30, 10, 10, 5)).setTo(255);
  const Appearance m = pooler.Pool(split);
  ASSERT_FALSE(m.empty());
  EXPECT_NEAR(m.values[0], 0.0, 1e-6);
  EXPECT_NEAR(m.values[1], 1.0, 1e-6);

  // Nothing to describe: no pixel, the whole image (equal to the mean), a mask of another size,
  // or no embedding at all.
  EXPECT_TRUE(pooler.Pool(cv::Mat::zeros(size, CV_8UC1)).empty());
  EXPECT_TRUE(pooler.Pool(cv::Mat(size, CV_8UC1, cv::Scalar(255))).empty());
  EXPECT_TRUE(pooler.Pool(cv::Mat(10, 10, CV_8UC1, cv::Scalar(255))).empty());
  const ImageEmbedding none;
  EXPECT_TRUE(EmbeddingPooler(none, size).Pool(top_left).empty());
  // Different kinds are never compared: a colour descriptor of the same mask is not comparable.
  const Appearance colour =
      ColourAppearance(cv::Mat(size, CV_8UC3, cv::Scalar(0, 0, 200)), top_left);
  EXPECT_FALSE(Comparable(a, colour));
}

}  // namespace
}  // namespace zeroreg
