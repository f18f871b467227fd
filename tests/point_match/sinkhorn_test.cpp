#include "point_match/sinkhorn.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

Eigen::MatrixXd RandomUnitRows(int n, int d, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd g(n, d);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < d; ++k) g(i, k) = static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5;
    g.row(i).normalize();
  }
  return g;
}

bool NoNanOrPositiveInf(const Eigen::MatrixXd& m) {
  return !m.hasNaN() && (m.array() < std::numeric_limits<double>::infinity()).all();
}

TEST(Sinkhorn, MarginalsConvergeToSuperGlueTargets) {
  const int n = 7, m = 5;
  const Eigen::MatrixXd gp = RandomUnitRows(n, 8, 1), gq = RandomUnitRows(m, 8, 2);
  SinkhornConfig cfg;
  cfg.iterations = 2000;
  cfg.temperature = 0.1;  // convergence slows as T -> 0 (the unregularised limit)
  const Eigen::MatrixXd p = SinkhornLogAssignment(gp * gq.transpose(), cfg).array().exp();
  const Eigen::VectorXd rows = p.rowwise().sum();
  const Eigen::RowVectorXd cols = p.colwise().sum();
  for (int i = 0; i < n; ++i) EXPECT_NEAR(rows(i), 1.0, 1e-6);
  EXPECT_NEAR(rows(n), m, 1e-6);  // the source dustbin row can absorb every target point
  for (int k = 0; k < m; ++k) EXPECT_NEAR(cols(k), 1.0, 1e-9);
  EXPECT_NEAR(cols(m), n, 1e-9);  // the target dustbin column can absorb every source point
}

// Reference: the log-domain iteration written out entry by entry (no shortcuts), to check the
// implementation's scaling form against it.
Eigen::MatrixXd ReferenceLogSinkhorn(const Eigen::MatrixXd& scores, const SinkhornConfig& cfg) {
  const Eigen::Index n = scores.rows(), m = scores.cols();
  Eigen::MatrixXd z = Eigen::MatrixXd::Constant(n + 1, m + 1, cfg.dustbin_score);
  z.topLeftCorner(n, m) = scores / cfg.temperature;
  Eigen::VectorXd log_a = Eigen::VectorXd::Zero(n + 1), log_b = Eigen::VectorXd::Zero(m + 1);
  log_a(n) = std::log(static_cast<double>(m));
  log_b(m) = std::log(static_cast<double>(n));
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n + 1), v = Eigen::VectorXd::Zero(m + 1);
  for (int it = 0; it < cfg.iterations; ++it) {
    for (Eigen::Index i = 0; i <= n; ++i) {
      double sum = 0;
      for (Eigen::Index j = 0; j <= m; ++j) sum += std::exp(z(i, j) + v(j));
      u(i) = log_a(i) - std::log(sum);
    }
    for (Eigen::Index j = 0; j <= m; ++j) {
      double sum = 0;
      for (Eigen::Index i = 0; i <= n; ++i) sum += std::exp(z(i, j) + u(i));
      v(j) = log_b(j) - std::log(sum);
    }
  }
  Eigen::MatrixXd log_p = z;
  log_p.colwise() += u;
  log_p.rowwise() += v.transpose();
  return log_p;
}

TEST(Sinkhorn, AgreesWithAPlainLogDomainReference) {
  const Eigen::MatrixXd gp = RandomUnitRows(12, 8, 5), gq = RandomUnitRows(9, 8, 6);
  for (double temperature : {0.03, 0.1, 0.5}) {
    SinkhornConfig cfg;
    cfg.temperature = temperature;
    cfg.iterations = temperature == 0.5 ? 0 : 20;  // 0 iterations: S' itself, in both forms
    const Eigen::MatrixXd scores = gp * gq.transpose();
    const Eigen::MatrixXd expected = ReferenceLogSinkhorn(scores, cfg);
    const Eigen::MatrixXd actual = SinkhornLogAssignment(scores, cfg);
    EXPECT_LT((expected - actual).cwiseAbs().maxCoeff(), 1e-9) << "T = " << temperature;
  }
}

TEST(Sinkhorn, OrthogonalDescriptorGoesToTheDustbin) {
  // Sources 0-2 equal targets 0-2; source 3 is orthogonal to every target.
  const Eigen::MatrixXd gp = Eigen::MatrixXd::Identity(4, 4);
  const Eigen::MatrixXd gq = Eigen::MatrixXd::Identity(3, 4);
  Eigen::MatrixXd log_p;
  const std::vector<SinkhornMatch> matches = MatchSinkhorn(gp, gq, {}, &log_p);
  ASSERT_EQ(log_p.rows(), 5);
  ASSERT_EQ(log_p.cols(), 4);
  ASSERT_EQ(matches.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(matches[i].source, i);
    EXPECT_EQ(matches[i].target, i);
    EXPECT_GT(matches[i].probability, 0.9);
  }
  EXPECT_GT(std::exp(log_p(3, 3)), 0.9);  // source 3's mass is in the dustbin column
}

TEST(Sinkhorn, IdenticalDescriptorSetsGiveTheIdentity) {
  const Eigen::MatrixXd g = RandomUnitRows(40, 32, 3);
  const std::vector<SinkhornMatch> matches = MatchSinkhorn(g, g);
  ASSERT_EQ(matches.size(), 40u);
  for (int i = 0; i < 40; ++i) {
    EXPECT_EQ(matches[i].source, i);
    EXPECT_EQ(matches[i].target, i);
  }
}

TEST(Sinkhorn, StableWithHugeScores) {
  // Scores scaled by 1e4 (logits up to 1e5 at temperature 0.1): exp would overflow without LSE.
  const Eigen::MatrixXd g = RandomUnitRows(30, 16, 4) * 100.0;
  Eigen::MatrixXd log_p;
  const std::vector<SinkhornMatch> matches = MatchSinkhorn(g, g, {}, &log_p);
  EXPECT_TRUE(NoNanOrPositiveInf(log_p));
  ASSERT_EQ(matches.size(), 30u);
  for (int i = 0; i < 30; ++i) {
    EXPECT_EQ(matches[i].target, i);
    EXPECT_GT(matches[i].probability, 0.9);
  }
  const Eigen::MatrixXd negative = SinkhornLogAssignment(-1e4 * Eigen::MatrixXd::Ones(5, 6));
  EXPECT_TRUE(NoNanOrPositiveInf(negative));
  EXPECT_TRUE(ExtractSinkhornMatches(negative).empty());  // everything goes to the dustbins
}

TEST(Sinkhorn, EmptyInputsGiveNoMatches) {
  const Eigen::MatrixXd g = RandomUnitRows(4, 8, 5);
  Eigen::MatrixXd log_p;
  EXPECT_TRUE(MatchSinkhorn(Eigen::MatrixXd(0, 8), g, {}, &log_p).empty());
  EXPECT_EQ(log_p.rows(), 1);
  EXPECT_EQ(log_p.cols(), 5);
  EXPECT_FALSE(log_p.hasNaN());
  EXPECT_TRUE(MatchSinkhorn(g, Eigen::MatrixXd(0, 3), {}, &log_p).empty());
  EXPECT_EQ(log_p.rows(), 5);
  EXPECT_EQ(log_p.cols(), 1);
  EXPECT_FALSE(log_p.hasNaN());
  EXPECT_TRUE(MatchSinkhorn(Eigen::MatrixXd(0, 8), Eigen::MatrixXd(0, 8)).empty());
}

TEST(Sinkhorn, MutualCheckKeepsOneOfTwoCompetingSources) {
  // Sources 0 and 1 are the same descriptor, equal to target 0: they must share its unit mass.
  Eigen::MatrixXd gp = Eigen::MatrixXd::Zero(3, 3), gq = Eigen::MatrixXd::Zero(2, 3);
  gp(0, 0) = gp(1, 0) = 1.0;
  gp(2, 1) = 1.0;
  gq(0, 0) = 1.0;
  gq(1, 1) = 1.0;
  SinkhornConfig cfg;
  const std::vector<SinkhornMatch> mutual = MatchSinkhorn(gp, gq, cfg);
  ASSERT_EQ(mutual.size(), 2u);
  EXPECT_EQ(mutual[0].source, 0);  // first on ties
  EXPECT_EQ(mutual[1].source, 2);
  EXPECT_NEAR(mutual[0].probability, 0.5, 0.05);
  cfg.mutual = false;
  EXPECT_EQ(MatchSinkhorn(gp, gq, cfg).size(), 3u);
  cfg.min_probability = 0.6;
  EXPECT_EQ(MatchSinkhorn(gp, gq, cfg).size(), 1u);
}

TEST(Sinkhorn, RejectsBadInput) {
  const Eigen::MatrixXd g = RandomUnitRows(3, 4, 6);
  EXPECT_THROW(MatchSinkhorn(g, RandomUnitRows(3, 5, 7)), InputError);
  SinkhornConfig cfg;
  cfg.temperature = 0.0;
  EXPECT_THROW(MatchSinkhorn(g, g, cfg), InputError);
  Eigen::MatrixXd bad = g;
  bad(1, 1) = std::nan("");
  EXPECT_THROW(MatchSinkhorn(bad, g), InputError);
  // The float overload used with float descriptors gives the same matches.
  EXPECT_EQ(
      MatchSinkhorn(Eigen::MatrixXf(g.cast<float>()), Eigen::MatrixXf(g.cast<float>())).size(), 3u);
}

// The whole-image path splits the kernel's columns among threads: the matches and
// their probabilities are bit-identical for any thread count, for column counts that do and do not
// divide into the blocks, and agree with the double-precision path.
TEST(Sinkhorn, SameMatchesWhateverTheThreadCount) {
  for (const auto& [n, m] : {std::pair<int, int>{700, 651}, {640, 3}, {3, 900}}) {
    Eigen::MatrixXd gp = RandomUnitRows(n, 64, 21), gq = RandomUnitRows(m, 64, 22);
    for (int k = 0; k < std::min(n, m) / 2; ++k) {
      gq.row(k) = (gp.row(k) + 0.4 * gq.row(k)).normalized();
    }
    const Eigen::MatrixXf fp = gp.cast<float>(), fq = gq.cast<float>();
    const std::vector<SinkhornMatch> one = MatchSinkhorn(fp, fq, {}, nullptr, 1);
    Eigen::MatrixXd log_p;
    const std::vector<SinkhornMatch> exact = MatchSinkhorn(gp, gq, {}, &log_p);
    if (n > 100 && m > 100) {
      ASSERT_GT(one.size(), 100u);
    }
    ASSERT_EQ(one.size(), exact.size()) << n << " x " << m;
    for (size_t k = 0; k < one.size(); ++k) {
      EXPECT_EQ(one[k].source, exact[k].source);
      EXPECT_EQ(one[k].target, exact[k].target);
      EXPECT_NEAR(one[k].probability, exact[k].probability, 1e-4);
    }
    for (const int threads : {2, 3, 8}) {
      const std::vector<SinkhornMatch> many = MatchSinkhorn(fp, fq, {}, nullptr, threads);
      ASSERT_EQ(many.size(), one.size()) << n << " x " << m << ", threads " << threads;
      for (size_t k = 0; k < one.size(); ++k) {
        EXPECT_EQ(many[k].source, one[k].source);
        EXPECT_EQ(many[k].target, one[k].target);
        EXPECT_EQ(many[k].probability, one[k].probability);  // bit for bit
      }
    }
  }
}

// The single-precision path taken for float descriptors (whole images) gives the matches of the
// double-precision log-domain path: the same pairs, probabilities within float rounding. Half the
// target points are noisy copies of source points, as in a real overlap.
TEST(Sinkhorn, SinglePrecisionPathMatchesDoublePrecision) {
  const int n = 300, m = 260;
  Eigen::MatrixXd gp = RandomUnitRows(n, 64, 11), gq = RandomUnitRows(m, 64, 12);
  for (int k = 0; k < m / 2; ++k) gq.row(k) = (gp.row(2 * k) + 0.4 * gq.row(k)).normalized();
  for (const double temperature : {0.03, 0.1}) {
    SinkhornConfig cfg;
    cfg.temperature = temperature;
    Eigen::MatrixXd log_p;  // asking for log P forces the double path
    const std::vector<SinkhornMatch> exact = MatchSinkhorn(gp, gq, cfg, &log_p);
    const std::vector<SinkhornMatch> single =
        MatchSinkhorn(Eigen::MatrixXf(gp.cast<float>()), Eigen::MatrixXf(gq.cast<float>()), cfg);
    ASSERT_GT(exact.size(), 100u);
    ASSERT_EQ(single.size(), exact.size()) << "T " << temperature;
    for (size_t k = 0; k < exact.size(); ++k) {
      EXPECT_EQ(single[k].source, exact[k].source);
      EXPECT_EQ(single[k].target, exact[k].target);
      EXPECT_NEAR(single[k].probability, exact[k].probability, 1e-4);
    }
  }
  // Logits spanning more than float's exponent range take the double path: still finite matches.
  SinkhornConfig sharp;
  sharp.temperature = 0.01;  // cosines in [-1, 1] span 200 logits
  EXPECT_EQ(
      MatchSinkhorn(Eigen::MatrixXf(gp.cast<float>()), Eigen::MatrixXf(gq.cast<float>()), sharp)
          .size(),
      MatchSinkhorn(gp, gq, sharp).size());
}

}  // namespace
}  // namespace zeroreg
