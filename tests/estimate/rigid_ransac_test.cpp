#include "estimate/rigid_ransac.hpp"

#include <gtest/gtest.h>

#include <random>

#include "eval/metrics.hpp"
#include "rigid_motion.hpp"

namespace zeroreg {
namespace {

using testing::MakeTransform;
// Correspondences for a known transform: `inliers` exact matches with Gaussian noise, then
// `outliers` random pairs, shuffled.
void MakeCorrespondences(const Transform& T, int inliers, int outliers, double noise, unsigned seed,
                         std::vector<Eigen::Vector3d>* source,
                         std::vector<Eigen::Vector3d>* target) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> box(-2.0, 2.0);
  std::normal_distribution<double> gauss(0.0, noise);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (int i = 0; i < inliers + outliers; ++i) {
    const Eigen::Vector3d p(box(rng), box(rng), box(rng) + 3.0);
    Eigen::Vector3d q = (T * p.homogeneous()).head<3>();
    if (i < inliers) {
      q += Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    } else {
      q = Eigen::Vector3d(box(rng), box(rng), box(rng) + 3.0);
    }
    pairs.emplace_back(p, q);
  }
  std::shuffle(pairs.begin(), pairs.end(), rng);
  for (const auto& [p, q] : pairs) {
    source->push_back(p);
    target->push_back(q);
  }
}

TEST(FitRigidTransform, RecoversExactTransform) {
  const Transform T = MakeTransform(0.7, {1, 2, 3}, {0.3, -1.2, 2.0});
  std::vector<Eigen::Vector3d> s, t;
  MakeCorrespondences(T, 50, 0, 0.0, 1, &s, &t);
  Transform estimate;
  ASSERT_TRUE(FitRigidTransform(s, t, {}, &estimate));
  EXPECT_LT((estimate - T).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR((estimate.topLeftCorner<3, 3>().determinant()), 1.0, 1e-12);
}

TEST(FitRigidTransform, RejectsCollinearAndTooFewPoints) {
  std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  Transform T;
  EXPECT_FALSE(FitRigidTransform(line, line, {}, &T));
  EXPECT_FALSE(FitRigidTransform(line, line, {0, 1}, &T));
}

TEST(EstimateRigidRansac, FindsTransformWithManyOutliers) {
  const Transform T = MakeTransform(0.4, {0.2, 1, 0.1}, {0.5, 0.1, -0.3});
  std::vector<Eigen::Vector3d> s, t;
  MakeCorrespondences(T, 100, 300, 0.005, 7, &s, &t);  // 75% outliers, 5 mm noise
  RansacConfig config;
  const RansacResult r = EstimateRigidRansac(s, t, config, 0);
  ASSERT_TRUE(r.found);
  EXPECT_LT(RotationErrorDeg(r.T_target_source, T), 0.5);
  EXPECT_LT(TranslationErrorM(r.T_target_source, T), 0.01);
  EXPECT_GE(r.num_inliers, 95);
  EXPECT_LE(r.num_inliers, 110);  // a few random pairs may fall within 5 cm by chance
}

TEST(EstimateRigidRansac, SameSeedSameOutputBitForBit) {
  const Transform T = MakeTransform(1.0, {1, 0, 1}, {1, 2, 3});
  std::vector<Eigen::Vector3d> s, t;
  MakeCorrespondences(T, 40, 160, 0.01, 3, &s, &t);
  const RansacResult a = EstimateRigidRansac(s, t, RansacConfig(), 42);
  const RansacResult b = EstimateRigidRansac(s, t, RansacConfig(), 42);
  EXPECT_TRUE((a.T_target_source.array() == b.T_target_source.array()).all());
  EXPECT_EQ(a.is_inlier, b.is_inlier);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(EstimateRigidRansac, NoStructureGivesFewInliers) {
  std::vector<Eigen::Vector3d> s, t;
  MakeCorrespondences(Transform::Identity(), 0, 200, 0.0, 11, &s, &t);
  const RansacResult r = EstimateRigidRansac(s, t, RansacConfig(), 0);
  EXPECT_LT(r.num_inliers, 10);
}

TEST(EstimateRigidRansac, TooFewCorrespondences) {
  std::vector<Eigen::Vector3d> s = {{0, 0, 1}, {1, 0, 1}}, t = s;
  const RansacResult r = EstimateRigidRansac(s, t, RansacConfig(), 0);
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.num_inliers, 0);
}

}  // namespace
}  // namespace zeroreg
