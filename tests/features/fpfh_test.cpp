// MutualFeatureMatches (brute force instead of a 33-d k-d tree): the same pairs and
// scores as a direct double loop, ties to the lower index, the same result for any thread count,
// and on real FPFH features of a scene and its rigidly moved copy (flat regions: many near-equal
// histograms) the same pairs as the definition, far more of them on their own moved copy than
// chance would put there.
#include "features/fpfh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

namespace zeroreg {
namespace {

FpfhCloud RandomFeatures(int dims, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> bin(0.0, 100.0);
  FpfhCloud c;
  c.features.resize(dims, n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < dims; ++i) c.features(i, j) = bin(rng);
  }
  return c;
}

// Squared Euclidean distance, summed in dimension order.
double SquaredDistance(const Eigen::MatrixXd& S, Eigen::Index s, const Eigen::MatrixXd& T,
                       Eigen::Index t) {
  double sum = 0;
  for (Eigen::Index k = 0; k < S.rows(); ++k) sum += (S(k, s) - T(k, t)) * (S(k, s) - T(k, t));
  return sum;
}

// The definition, one distance at a time: the closest and second-closest target of each source,
// the closest source of each target, strict comparisons in index order (ties to the lower index).
std::vector<FeaturePair> Reference(const FpfhCloud& source, const FpfhCloud& target) {
  const Eigen::MatrixXd& S = source.features;
  const Eigen::MatrixXd& T = target.features;
  std::vector<FeaturePair> out;
  for (Eigen::Index s = 0; s < S.cols(); ++s) {
    double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
    Eigen::Index t1 = -1;
    for (Eigen::Index t = 0; t < T.cols(); ++t) {
      const double d = SquaredDistance(S, s, T, t);
      if (d < d1) {
        d2 = d1;
        d1 = d;
        t1 = t;
      } else if (d < d2) {
        d2 = d;
      }
    }
    double back = std::numeric_limits<double>::infinity();
    Eigen::Index s1 = -1;
    for (Eigen::Index k = 0; k < S.cols(); ++k) {
      const double d = SquaredDistance(S, k, T, t1);
      if (d < back) {
        back = d;
        s1 = k;
      }
    }
    if (s1 != s) continue;
    FeaturePair p;
    p.source = static_cast<int>(s);
    p.target = static_cast<int>(t1);
    p.score = d2 > 0 ? static_cast<float>(1.0 - std::sqrt(d1) / std::sqrt(d2)) : 0.0f;
    out.push_back(p);
  }
  return out;
}

void ExpectSame(const std::vector<FeaturePair>& a, const std::vector<FeaturePair>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].source, b[i].source) << i;
    EXPECT_EQ(a[i].target, b[i].target) << i;
    EXPECT_EQ(a[i].score, b[i].score) << i;  // bit for bit
  }
}

TEST(MutualFeatureMatches, AgreesWithTheDirectDefinition) {
  // More sources than one block of the distance matrix (256), so that blocks are merged.
  const FpfhCloud s = RandomFeatures(33, 700, 1), t = RandomFeatures(33, 650, 2);
  const std::vector<FeaturePair> expected = Reference(s, t);
  ASSERT_GT(expected.size(), 20u);
  ExpectSame(MutualFeatureMatches(s, t, 1), expected);
}

TEST(MutualFeatureMatches, SameResultForAnyThreadCount) {
  const FpfhCloud s = RandomFeatures(33, 1100, 3), t = RandomFeatures(33, 900, 4);
  const std::vector<FeaturePair> one = MutualFeatureMatches(s, t, 1);
  for (int threads : {2, 3, 8}) {
    const std::vector<FeaturePair> many = MutualFeatureMatches(s, t, threads);
    ASSERT_EQ(many.size(), one.size()) << threads;
    for (size_t i = 0; i < one.size(); ++i) {
      EXPECT_EQ(many[i].source, one[i].source);
      EXPECT_EQ(many[i].target, one[i].target);
      EXPECT_EQ(many[i].score, one[i].score);  // bit for bit
    }
  }
}

TEST(MutualFeatureMatches, TiesGoToTheLowerIndex) {
  // Three identical target features (as FPFH gives isolated points: all-zero histograms) in
  // different blocks' reach: the source matches the first, with a score of 0 (ambiguous).
  FpfhCloud s = RandomFeatures(33, 300, 5), t = RandomFeatures(33, 40, 6);
  s.features.col(0).setZero();
  s.features.col(299).setZero();
  for (int j : {7, 8, 30}) t.features.col(j).setZero();
  const std::vector<FeaturePair> m = MutualFeatureMatches(s, t, 2);
  bool found = false;
  for (const FeaturePair& p : m) {
    EXPECT_NE(p.source, 299);  // the closest source of target 7 is source 0, not 299
    if (p.source == 0) {
      found = true;
      EXPECT_EQ(p.target, 7);
      EXPECT_EQ(p.score, 0.0f);
    }
  }
  EXPECT_TRUE(found);
}

TEST(MutualFeatureMatches, FewerThanTwoFeaturesGiveNoMatches) {
  EXPECT_TRUE(MutualFeatureMatches(RandomFeatures(33, 1, 7), RandomFeatures(33, 50, 8)).empty());
  EXPECT_TRUE(MutualFeatureMatches(RandomFeatures(33, 50, 9), RandomFeatures(33, 1, 10)).empty());
}

TEST(MutualFeatureMatches, RealFpfhOfAMovedCopyAgreesWithTheDefinitionAndFindsTheMotion) {
  // A box-shaped room corner with a few bumps on a 1 cm grid: FPFH at 5 cm voxels, then the same
  // points moved rigidly. FPFH is rotation invariant, so a point's own moved copy has (nearly)
  // the same histogram.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 150; ++i) {
    for (int j = 0; j < 150; ++j) {
      const double u = i * 0.01, v = j * 0.01;
      const double bump = 0.05 * std::exp(-((u - 0.5) * (u - 0.5) + (v - 0.9) * (v - 0.9)) / 0.01);
      points.emplace_back(u, v, bump);        // floor
      points.emplace_back(u, 0.0, v);         // wall
      points.emplace_back(0.0, u, v + bump);  // other wall
    }
  }
  const Eigen::Affine3d move = Eigen::Translation3d(0.3, -0.2, 1.0) *
                               Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  std::vector<Eigen::Vector3d> moved;
  for (const Eigen::Vector3d& p : points) moved.push_back(move * p);
  FpfhParams params;
  const FpfhCloud a = ComputeFpfh(points, params), b = ComputeFpfh(moved, params);
  const std::vector<FeaturePair> m = MutualFeatureMatches(a, b, 2);
  ASSERT_GT(m.size(), 50u);
  ExpectSame(m, Reference(a, b));
  // Chance: a 10 cm disc is ~0.5 % of the 6.75 m^2 of surface; flat points are ambiguous.
  int close = 0;
  for (const FeaturePair& p : m) {
    const Eigen::Vector3d from = move * a.points[static_cast<size_t>(p.source)];
    if ((from - b.points[static_cast<size_t>(p.target)]).norm() < 0.1) ++close;
  }
  EXPECT_GT(close, static_cast<int>(m.size()) / 10) << close << " of " << m.size();
}

}  // namespace
}  // namespace zeroreg
