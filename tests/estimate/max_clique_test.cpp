#include "estimate/max_clique.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <thread>

#include "estimate/rigid_ransac.hpp"
#include "eval/metrics.hpp"
#include "rigid_motion.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using testing::Apply;
using testing::MakeTransform;

// A room-sized scene: `inliers` correspondences of T with Gaussian noise (sigma metres per axis),
// `cluster` correspondences consistent with a second rigid motion (a structured outlier set, as
// repeated furniture gives), and `outliers` uniform random pairs in the same 4 m box. Shuffled;
// truth[i] says whether i is one of T's inliers.
struct Synthetic {
  std::vector<Eigen::Vector3d> source, target;
  std::vector<float> scores;
  std::vector<bool> truth;
};
Synthetic MakeScene(const Transform& T, int inliers, int cluster, int outliers, double sigma,
                    unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> box(-2.0, 2.0);
  std::normal_distribution<double> gauss(0.0, sigma);
  const Transform wrong = MakeTransform(2.0, {0.3, -1, 0.5}, {1.0, -0.5, 0.7});
  struct Row {
    Eigen::Vector3d s, t;
    bool inlier;
  };
  std::vector<Row> rows;
  auto noisy = [&](const Eigen::Vector3d& p) {
    Eigen::Vector3d q = p;
    for (int k = 0; k < 3; ++k) q[k] += gauss(rng);
    return q;
  };
  for (int i = 0; i < inliers + cluster + outliers; ++i) {
    const Eigen::Vector3d p(box(rng), box(rng), box(rng) + 3.0);
    if (i < inliers) {
      rows.push_back({p, noisy(Apply(T, p)), true});
    } else if (i < inliers + cluster) {
      rows.push_back({p, noisy(Apply(wrong, p)), false});
    } else {
      rows.push_back({p, Eigen::Vector3d(box(rng), box(rng), box(rng) + 3.0), false});
    }
  }
  std::shuffle(rows.begin(), rows.end(), rng);
  Synthetic out;
  for (const Row& r : rows) {
    out.source.push_back(r.s);
    out.target.push_back(r.t);
    out.scores.push_back(1.0f);
    out.truth.push_back(r.inlier);
  }
  return out;
}

RansacConfig CliqueConfig() {
  RansacConfig c;
  c.estimator = "clique";
  return c;
}

TEST(MaximumClique, FindsThePlantedCliqueInARandomGraph) {
  // G(300, 0.1) has cliques of about 4; a planted clique of 12 is the unique maximum.
  const int n = 300;
  std::mt19937 rng(5);
  std::bernoulli_distribution edge(0.1);
  std::vector<std::vector<bool>> a(n, std::vector<bool>(n, false));
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) a[i][j] = a[j][i] = edge(rng);
  }
  const std::vector<int> planted = {3, 17, 42, 77, 101, 150, 151, 199, 230, 260, 280, 299};
  for (int i : planted) {
    for (int j : planted) {
      if (i != j) a[i][j] = true;
    }
  }
  std::vector<std::vector<int>> adjacency(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (a[i][j]) adjacency[i].push_back(j);
    }
  }
  const CliqueSearchResult r = MaximumClique(adjacency, 1000000);
  EXPECT_TRUE(r.exact);
  EXPECT_EQ(r.clique, planted);
}

TEST(MaximumClique, EmptyAndEdgelessGraphs) {
  EXPECT_TRUE(MaximumClique({}, 10).clique.empty());
  const CliqueSearchResult r = MaximumClique({{}, {}, {}}, 10);
  ASSERT_EQ(r.clique.size(), 1u);  // any single vertex; the lowest index by the tie rule
  EXPECT_EQ(r.clique[0], 0);
}

TEST(MaximumClique, BudgetStopsTheSearchAndSaysSo) {
  // G(120, 0.5): colouring bounds are weak on dense random graphs, so one node proves nothing,
  // while the full search finishes and finds a clique at least as large.
  const int n = 120;
  std::mt19937 rng(9);
  std::bernoulli_distribution edge(0.5);
  std::vector<std::vector<int>> adjacency(n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (edge(rng)) {
        adjacency[i].push_back(j);
        adjacency[j].push_back(i);
      }
    }
  }
  const CliqueSearchResult tight = MaximumClique(adjacency, 1);
  EXPECT_FALSE(tight.exact);
  EXPECT_EQ(tight.search_nodes, 2);  // the one allowed node and the refused one
  const CliqueSearchResult full = MaximumClique(adjacency, 10000000);
  EXPECT_TRUE(full.exact);
  EXPECT_GE(full.clique.size(), tight.clique.size());
  for (int a : full.clique) {  // it is a clique
    for (int b : full.clique) {
      if (a != b) {
        EXPECT_NE(std::find(adjacency[a].begin(), adjacency[a].end(), b), adjacency[a].end());
      }
    }
  }
}

// The estimator at 5 %, 3 % and 2 % inliers among uniform outliers: the transform comes out
// within a few millimetres and a tenth of a degree, and the inliers are T's own.
class CliqueLowInlierRatio : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(CliqueLowInlierRatio, RecoversTheTransform) {
  const auto [inliers, total] = GetParam();
  const Transform T = MakeTransform(0.9, {0.2, 1, -0.4}, {0.6, -0.3, 0.4});
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Synthetic s = MakeScene(T, inliers, 0, total - inliers, 0.005, seed);
    const RansacResult r = EstimateRigid(s.source, s.target, s.scores, CliqueConfig(), 0);
    ASSERT_TRUE(r.found) << "seed " << seed;
    EXPECT_LT(RotationErrorDeg(r.T_target_source, T), 0.5) << "seed " << seed;
    EXPECT_LT(TranslationErrorM(r.T_target_source, T), 0.01) << "seed " << seed;
    int true_positive = 0;
    for (size_t i = 0; i < s.truth.size(); ++i) true_positive += s.truth[i] && r.is_inlier[i];
    EXPECT_GE(true_positive, inliers - 1) << "seed " << seed;  // a 3-sigma tail may fall out
    EXPECT_LE(r.num_inliers, inliers + 5) << "seed " << seed;  // random pairs within 5 cm
  }
}

INSTANTIATE_TEST_SUITE_P(FiveThreeTwoPercent, CliqueLowInlierRatio,
                         ::testing::Values(std::make_tuple(50, 1000), std::make_tuple(30, 1000),
                                           std::make_tuple(20, 1000)));

TEST(CliqueEstimator, RansacWithItsDefaultBudgetFailsWhereTheCliqueSucceeds) {
  // 2 % inliers: an all-inlier 3-sample has probability 8e-6, so RANSAC's 50,000 iterations draw
  // one with probability 1 - (1 - 8e-6)^50000 = 0.33. Over 6 scenes RANSAC must miss at least
  // once (probability of never missing ~ 0.33^6 = 1e-3) and the clique must never miss.
  const Transform T = MakeTransform(0.5, {1, 0.3, 0.2}, {-0.4, 0.8, 0.1});
  int ransac_failures = 0;
  for (unsigned seed = 11; seed <= 16; ++seed) {
    const Synthetic s = MakeScene(T, 20, 0, 980, 0.005, seed);
    const RansacResult ransac = EstimateRigidRansac(s.source, s.target, RansacConfig(), seed);
    const bool ransac_right = ransac.found && RotationErrorDeg(ransac.T_target_source, T) < 2 &&
                              TranslationErrorM(ransac.T_target_source, T) < 0.05;
    ransac_failures += !ransac_right;
    const RansacResult clique = EstimateRigid(s.source, s.target, s.scores, CliqueConfig(), seed);
    ASSERT_TRUE(clique.found);
    EXPECT_LT(RotationErrorDeg(clique.T_target_source, T), 0.5) << "seed " << seed;
    EXPECT_LT(TranslationErrorM(clique.T_target_source, T), 0.01) << "seed " << seed;
  }
  EXPECT_GE(ransac_failures, 1);
}

TEST(CliqueEstimator, PrefersTheLargerOfTwoRigidlyConsistentClusters) {
  // 40 inliers of T, 25 correspondences of another rigid motion, 935 uniform outliers (4 %):
  // both clusters are cliques; the larger is T's.
  const Transform T = MakeTransform(-0.7, {0, 1, 0.2}, {0.2, 0.1, -0.5});
  for (unsigned seed = 21; seed <= 23; ++seed) {
    const Synthetic s = MakeScene(T, 40, 25, 935, 0.005, seed);
    const RansacResult r = EstimateRigid(s.source, s.target, s.scores, CliqueConfig(), 0);
    ASSERT_TRUE(r.found);
    EXPECT_LT(RotationErrorDeg(r.T_target_source, T), 0.5) << "seed " << seed;
    EXPECT_LT(TranslationErrorM(r.T_target_source, T), 0.01) << "seed " << seed;
    EXPECT_GE(r.num_inliers, 38);
    EXPECT_LE(r.num_inliers, 45);
  }
}

TEST(CliqueEstimator, CapKeepsTheHighestScores) {
  // 3000 correspondences, cap 1500: the 30 inliers score highest, so the cap keeps them; with
  // their scores lowest the cap drops them and the estimate is wrong.
  const Transform T = MakeTransform(0.3, {1, 1, 0}, {0.1, 0.2, 0.3});
  Synthetic s = MakeScene(T, 30, 0, 2970, 0.005, 31);
  for (size_t i = 0; i < s.scores.size(); ++i) s.scores[i] = s.truth[i] ? 0.9f : 0.5f;
  RansacConfig config = CliqueConfig();
  const RansacResult kept = EstimateRigid(s.source, s.target, s.scores, config, 0);
  ASSERT_TRUE(kept.found);
  EXPECT_LT(RotationErrorDeg(kept.T_target_source, T), 0.5);
  for (size_t i = 0; i < s.scores.size(); ++i) s.scores[i] = s.truth[i] ? 0.1f : 0.5f;
  const RansacResult dropped = EstimateRigid(s.source, s.target, s.scores, config, 0);
  EXPECT_FALSE(dropped.found && RotationErrorDeg(dropped.T_target_source, T) < 2);
}

TEST(CliqueEstimator, DeterministicAcrossRunsSeedsAndThreads) {
  const Transform T = MakeTransform(1.1, {0.5, 0.5, 1}, {0.3, 0.3, 0.3});
  const Synthetic s = MakeScene(T, 30, 15, 955, 0.01, 41);
  const RansacResult first = EstimateRigid(s.source, s.target, s.scores, CliqueConfig(), 1);
  std::vector<RansacResult> results(4);
  std::vector<std::thread> threads;
  for (size_t k = 0; k < results.size(); ++k) {
    threads.emplace_back([&, k] {
      results[k] = EstimateRigid(s.source, s.target, s.scores, CliqueConfig(), 100 + k);
    });
  }
  for (std::thread& t : threads) t.join();
  for (const RansacResult& r : results) {
    EXPECT_EQ(r.T_target_source, first.T_target_source);  // bit for bit
    EXPECT_EQ(r.is_inlier, first.is_inlier);
    EXPECT_EQ(r.iterations, first.iterations);
  }
}

TEST(CliqueEstimator, TooFewOrDegenerateCorrespondences) {
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_FALSE(EstimateRigid(two, two, {}, CliqueConfig(), 0).found);
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  EXPECT_FALSE(EstimateRigid(line, line, {}, CliqueConfig(), 0).found);
}

TEST(CliqueEstimator, UnknownEstimatorNameIsAnInputError) {
  RansacConfig c;
  c.estimator = "teaser";
  try {
    EstimateRigid({}, {}, {}, c, 0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ransac.estimator"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("teaser"), std::string::npos);
  }
}

}  // namespace
}  // namespace zeroreg
