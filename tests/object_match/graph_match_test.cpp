#include "object_match/graph_match.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <limits>

#include "graph/scene_graph.hpp"
#include "object_match/synthetic_scenes.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using testing::Gaussian;
using testing::MakeScenePair;
using testing::ScenePair;
using testing::Uniform;

Eigen::MatrixXd AssignmentMatrix(const std::vector<int>& a, int m) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(a.size()), m);
  for (std::size_t j = 0; j < a.size(); ++j) {
    if (a[j] >= 0) x(static_cast<Eigen::Index>(j), a[j]) = 1.0;
  }
  return x;
}

// E(X) straight from the matrices: ||W_p - X W_q X^T||_F^2 - alpha <C, X> + tau 1^T X 1, with
// the ||X W_q X^T||^2 part of the norm weighted by beta (= 1: the plain Frobenius norm).
double DirectEnergy(const Eigen::MatrixXd& wp, const Eigen::MatrixXd& wq, const Eigen::MatrixXd& c,
                    const std::vector<int>& a, const ObjectMatchConfig& cfg) {
  const Eigen::MatrixXd x = AssignmentMatrix(a, static_cast<int>(wq.rows()));
  const Eigen::MatrixXd xwx = x * wq * x.transpose();
  const double beta = cfg.target_edge_weight;
  const double frobenius =
      beta == 1.0 ? (wp - xwx).squaredNorm()
                  : wp.squaredNorm() - 2.0 * wp.cwiseProduct(xwx).sum() + beta * xwx.squaredNorm();
  return frobenius - cfg.node_weight * c.cwiseProduct(x).sum() + cfg.match_cost * x.sum();
}

// Minimum of DirectEnergy over every partial injection (independent of the solvers' algebra).
void Enumerate(const Eigen::MatrixXd& wp, const Eigen::MatrixXd& wq, const Eigen::MatrixXd& c,
               const ObjectMatchConfig& cfg, const MatchMask& allowed, std::vector<int>& a,
               std::vector<char>& used, int j, double& best, std::uint64_t& count) {
  if (j == static_cast<int>(a.size())) {
    ++count;
    best = std::min(best, DirectEnergy(wp, wq, c, a, cfg));
    return;
  }
  a[j] = -1;
  Enumerate(wp, wq, c, cfg, allowed, a, used, j + 1, best, count);
  for (int k = 0; k < wq.rows(); ++k) {
    if (used[k] || (allowed.size() != 0 && !allowed(j, k))) continue;
    used[k] = 1;
    a[j] = k;
    Enumerate(wp, wq, c, cfg, allowed, a, used, j + 1, best, count);
    used[k] = 0;
  }
  a[j] = -1;
}

double BruteForceEnergy(const Eigen::MatrixXd& wp, const Eigen::MatrixXd& wq,
                        const Eigen::MatrixXd& c, const ObjectMatchConfig& cfg,
                        const MatchMask& allowed = MatchMask(), std::uint64_t* count = nullptr) {
  std::vector<int> a(static_cast<std::size_t>(wp.rows()), -1);
  std::vector<char> used(static_cast<std::size_t>(wq.rows()), 0);
  double best = std::numeric_limits<double>::infinity();
  std::uint64_t n = 0;
  Enumerate(wp, wq, c, cfg, allowed, a, used, 0, best, n);
  if (count != nullptr) *count = n;
  return best;
}

struct Instance {
  Eigen::MatrixXd wp, wq, c;
};

// Scene-graph instances (kNN graphs of random layouts) or, when dense, arbitrary non-symmetric
// non-negative matrices with a non-zero diagonal, to exercise every term of the algebra.
Instance RandomInstance(int n, int m, bool dense, std::mt19937_64& rng) {
  Instance in;
  if (dense) {
    auto rand_matrix = [&](int r, int cols) {
      Eigen::MatrixXd a(r, cols);
      for (int i = 0; i < r; ++i) {
        for (int k = 0; k < cols; ++k) a(i, k) = Uniform(rng) < 0.5 ? 0.0 : Uniform(rng, 0, 2);
      }
      return a;
    };
    in.wp = rand_matrix(n, n);
    in.wq = rand_matrix(m, m);
    in.c = rand_matrix(n, m);
    return in;
  }
  const Eigen::MatrixXd emb = testing::ClassEmbeddings(3, 8, rng);
  auto scene = [&](int count, Eigen::MatrixXd& sem) {
    Eigen::MatrixXd cen(count, 3);
    sem.resize(count, emb.cols());
    for (int i = 0; i < count; ++i) {
      cen.row(i) << Uniform(rng, 0, 4), Uniform(rng, 0, 4), Uniform(rng, 0, 1);
      sem.row(i) = emb.row(static_cast<Eigen::Index>(rng() % 3));
    }
    return BuildAffinityMatrix(cen, sem, {2, true});
  };
  Eigen::MatrixXd sp, sq;
  in.wp = scene(n, sp);
  in.wq = scene(m, sq);
  in.c = NodeSimilarity(sp, sq);
  return in;
}

TEST(GraphMatch, ScoreAndEnergyAgreeWithTheFrobeniusFormOfEq2) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 6), m = 1 + static_cast<int>(rng() % 6);
    const Instance in = RandomInstance(n, m, trial % 2 == 0, rng);
    ObjectMatchConfig cfg;
    cfg.node_weight = Uniform(rng, 0, 3);
    cfg.match_cost = Uniform(rng, -1, 2);
    cfg.target_edge_weight = trial % 3 == 0 ? 1.0 : Uniform(rng, 0, 2);
    // A random partial injection.
    std::vector<int> targets(m);
    std::iota(targets.begin(), targets.end(), 0);
    std::shuffle(targets.begin(), targets.end(), rng);
    std::vector<int> a(n, -1);
    for (int j = 0; j < std::min(n, m); ++j) a[j] = rng() % 3 == 0 ? -1 : targets[j];
    const double e = GraphMatchEnergy(in.wp, in.wq, in.c, a, cfg);
    EXPECT_NEAR(e, DirectEnergy(in.wp, in.wq, in.c, a, cfg), 1e-9);
    EXPECT_NEAR(GraphMatchScore(in.wp, in.wq, in.c, a, cfg), in.wp.squaredNorm() - e, 1e-9);
  }
  // With alpha = 1, tau = 0 and a full assignment, E is Eq. 2 as printed (tr(C X) as <C, X>).
  const Eigen::MatrixXd wp{{0, 2}, {2, 0}}, wq{{0, 1.5}, {1.5, 0}}, c{{2, 1}, {1, 2}};
  ObjectMatchConfig eq2;
  eq2.match_cost = 0.0;
  EXPECT_NEAR(GraphMatchEnergy(wp, wq, c, {0, 1}, eq2), 2 * 0.25 - 4, 1e-12);
  EXPECT_THROW(GraphMatchEnergy(wp, wq, c, {0, 0}, eq2), InputError);
  EXPECT_THROW(GraphMatchEnergy(wp, wq, c, {0, 2}, eq2), InputError);
}

TEST(GraphMatch, CountPartialInjections) {
  EXPECT_EQ(CountPartialInjections(0, 5), 1u);
  EXPECT_EQ(CountPartialInjections(2, 3), 13u);  // 1 + 2*3 + 3*2
  EXPECT_EQ(CountPartialInjections(6, 6), 13327u);
  EXPECT_EQ(CountPartialInjections(7, 7), 130922u);
  EXPECT_EQ(CountPartialInjections(60, 60), std::numeric_limits<std::uint64_t>::max());
  std::mt19937_64 rng(1);
  const Instance in = RandomInstance(4, 5, true, rng);
  std::uint64_t count = 0;
  BruteForceEnergy(in.wp, in.wq, in.c, {}, MatchMask(), &count);
  EXPECT_EQ(count, CountPartialInjections(4, 5));
}

TEST(GraphMatch, ExactSolverEqualsBruteForce) {
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 120; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 5), m = 1 + static_cast<int>(rng() % 5);
    const Instance in = RandomInstance(n, m, trial % 3 == 0, rng);
    ObjectMatchConfig cfg;
    cfg.node_weight = trial % 4 == 0 ? 1.0 : Uniform(rng, 0, 3);
    cfg.match_cost = trial % 4 == 0 ? 0.0 : Uniform(rng, -1, 3);
    if (trial % 4 == 2) cfg.target_edge_weight = trial % 8 == 2 ? 0.0 : Uniform(rng, 0.1, 2);
    MatchMask mask;
    if (trial % 5 == 1) {
      mask.resize(n, m);
      for (int j = 0; j < n; ++j) {
        for (int k = 0; k < m; ++k) mask(j, k) = rng() % 3 != 0;
      }
    }
    const ObjectMatchResult r = MatchObjectsExact(in.wp, in.wq, in.c, cfg, mask);
    const double brute = BruteForceEnergy(in.wp, in.wq, in.c, cfg, mask);
    EXPECT_NEAR(r.energy, brute, 1e-9) << "trial " << trial;
    EXPECT_NEAR(r.energy, DirectEnergy(in.wp, in.wq, in.c, r.source_to_target, cfg), 1e-9);
    for (const ObjectPair& p : r.pairs) {
      if (mask.size() != 0) {
        EXPECT_TRUE(mask(p.source, p.target));
      }
      EXPECT_EQ(p.node_similarity, in.c(p.source, p.target));
    }
  }
}

// Fraction of the true pairs recovered, and fraction of the returned pairs that are true.
std::pair<double, double> RecallPrecision(const std::vector<int>& a, const std::vector<int>& t) {
  int correct = 0, truths = 0, matched = 0;
  for (std::size_t j = 0; j < t.size(); ++j) {
    truths += t[j] >= 0;
    matched += a[j] >= 0;
    correct += a[j] >= 0 && a[j] == t[j];
  }
  return {truths ? static_cast<double>(correct) / truths : 1.0,
          matched ? static_cast<double>(correct) / matched : 1.0};
}

// Synthetic scans of a room: the target sees 80% of the source (the part next to its own new
// area, which holds n / 6 extra objects), rigidly moved, shuffled, 2 cm centroid noise, 12 object
// classes with CLIP-like embeddings (cos ~ 0.5 between classes). Solved as the pipeline does, with
// the label-compatibility mask. (Without labels, kNN graphs of random layouts have many
// near-isomorphisms and the optimum of Eq. 2 is often not the truth: docs/MATCHING.md.)
TEST(GraphMatch, ApproximateSolverRecoversKnownCorrespondence) {
  ObjectMatchConfig cfg;
  cfg.solver = ObjectMatchSolver::kApproximate;
  for (int n : {10, 15, 20, 25, 30}) {
    double sum_recall = 0, sum_precision = 0, max_ms = 0;
    const int scenes = 8;
    for (int seed = 0; seed < scenes; ++seed) {
      const ScenePair s = MakeScenePair(n, 0.8, n / 6, 0.02, 12, 1000 + 10 * n + seed);
      const Eigen::MatrixXd wp = BuildAffinityMatrix(s.centroids_p, s.semantics_p);
      const Eigen::MatrixXd wq = BuildAffinityMatrix(s.centroids_q, s.semantics_q);
      const Eigen::MatrixXd c = NodeSimilarity(s.semantics_p, s.semantics_q);
      const MatchMask mask = LabelCompatibilityMask(s.labels_p, s.labels_q);
      const auto t0 = std::chrono::steady_clock::now();
      const ObjectMatchResult r = MatchObjects(wp, wq, c, cfg, mask);
      max_ms = std::max(
          max_ms,
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      const auto [recall, precision] = RecallPrecision(r.source_to_target, s.truth);
      EXPECT_GE(recall, 0.75) << "n " << n << " seed " << seed;
      EXPECT_GE(precision, 0.75) << "n " << n << " seed " << seed;
      // The truth is feasible: the solver must not end below it.
      EXPECT_GE(r.score, GraphMatchScore(wp, wq, c, s.truth, cfg) - 1e-9) << n << " " << seed;
      sum_recall += recall;
      sum_precision += precision;
    }
    std::printf("  n=%d: mean recall %.3f, mean precision %.3f, slowest %.1f ms\n", n,
                sum_recall / scenes, sum_precision / scenes, max_ms);
    EXPECT_GE(sum_recall / scenes, 0.9) << "n " << n;
    EXPECT_GE(sum_precision / scenes, 0.9) << "n " << n;
  }
}

TEST(GraphMatch, ApproximateSolverMostlyFindsTheExactOptimumOnSmallInstances) {
  std::mt19937_64 rng(5);
  int equal = 0, trials = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 4), m = 3 + static_cast<int>(rng() % 4);
    const Instance in = RandomInstance(n, m, false, rng);
    const ObjectMatchConfig cfg;
    const ObjectMatchResult exact = MatchObjectsExact(in.wp, in.wq, in.c, cfg);
    const ObjectMatchResult approx = MatchObjectsApproximate(in.wp, in.wq, in.c, cfg);
    EXPECT_LE(approx.score, exact.score + 1e-9);  // exact is optimal
    equal += approx.score >= exact.score - 1e-9;
    ++trials;
  }
  std::printf("  approximate == exact optimum on %d / %d small instances\n", equal, trials);
  EXPECT_GE(equal, trials * 8 / 10);
}

TEST(GraphMatch, AutoChoosesBySizeAndExactIsFastAtTheLimit) {
  ObjectMatchConfig cfg;
  std::mt19937_64 rng(9);
  const Instance small = RandomInstance(8, 8, false, rng);
  const auto t0 = std::chrono::steady_clock::now();
  const ObjectMatchResult r = MatchObjects(small.wp, small.wq, small.c, cfg);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.solver, ObjectMatchSolver::kExact);
  std::printf("  exact 8x8: %.2f ms, %llu search nodes (of %llu leaves)\n", ms,
              static_cast<unsigned long long>(r.search_nodes),
              static_cast<unsigned long long>(CountPartialInjections(8, 8)));
  const Instance big = RandomInstance(9, 8, false, rng);
  EXPECT_EQ(MatchObjects(big.wp, big.wq, big.c, cfg).solver, ObjectMatchSolver::kApproximate);
  cfg.solver = ObjectMatchSolver::kNodeOnly;
  EXPECT_EQ(MatchObjects(big.wp, big.wq, big.c, cfg).solver, ObjectMatchSolver::kNodeOnly);
  EXPECT_EQ(ObjectMatchSolverFromString("approximate"), ObjectMatchSolver::kApproximate);
  EXPECT_EQ(ToString(ObjectMatchSolver::kNodeOnly), "node_only");
  EXPECT_THROW(ObjectMatchSolverFromString("qap"), InputError);
}

// "Which chair?": a table with four chairs around it. All chairs have the same semantic vector, so
// node similarity cannot tell them apart; only their neighbours can: a lamp behind chair 1, a
// plant and a tv behind chair 2, a bin behind chair 3, nothing behind chair 4. The target is the
// same room rigidly moved and shuffled.
struct ChairRoom {
  Eigen::MatrixXd centroids;
  std::vector<std::string> labels;
};

ChairRoom MakeChairRoom() {
  ChairRoom room;
  std::vector<Eigen::Vector3d> p;
  p.emplace_back(0.03, 0.02, 0.7);  // off-centre: no two chairs at the same distance
  room.labels.push_back("table");
  // Angles slightly off 90 degrees so that no two distances tie.
  const double angles_deg[4] = {0, 85, 183, 271};
  for (int i = 0; i < 4; ++i) {
    const double a = angles_deg[i] * M_PI / 180.0;
    p.emplace_back(0.8 * std::cos(a), 0.8 * std::sin(a), 0.45);
    room.labels.push_back("chair");
  }
  struct Behind {
    int chair;
    double radius;
    const char* label;
  };
  const Behind behind[4] = {{0, 1.5, "lamp"}, {1, 1.5, "plant"}, {1, 2.2, "tv"}, {2, 1.5, "bin"}};
  for (const Behind& b : behind) {
    const double a = angles_deg[b.chair] * M_PI / 180.0;
    p.emplace_back(b.radius * std::cos(a), b.radius * std::sin(a), 0.6);
    room.labels.push_back(b.label);
  }
  room.centroids.resize(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t i = 0; i < p.size(); ++i) {
    room.centroids.row(static_cast<Eigen::Index>(i)) = p[i];
  }
  return room;
}

// One-hot label vectors: the "without CLIP" mode of the pipeline.
Eigen::MatrixXd OneHot(const std::vector<std::string>& labels,
                       const std::vector<std::string>& vocab) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(labels.size()),
                                            static_cast<Eigen::Index>(vocab.size()));
  for (std::size_t i = 0; i < labels.size(); ++i) {
    s(static_cast<Eigen::Index>(i),
      std::find(vocab.begin(), vocab.end(), labels[i]) - vocab.begin()) = 1.0;
  }
  return s;
}

TEST(GraphMatch, WhichChairIsResolvedByTheSceneGraphNotByNodeSimilarity) {
  const ChairRoom room = MakeChairRoom();
  const std::vector<std::string> vocab{"table", "chair", "lamp", "plant", "tv", "bin"};
  const int n = static_cast<int>(room.labels.size());
  const Eigen::MatrixXd sem_p = OneHot(room.labels, vocab);
  const Eigen::Isometry3d motion =
      Eigen::Translation3d(2.0, -1.0, 0.1) * Eigen::AngleAxisd(2.2, Eigen::Vector3d::UnitZ());
  int node_only_wrong_runs = 0;
  for (std::uint64_t seed = 0; seed < 8; ++seed) {
    std::mt19937_64 rng(seed);
    std::vector<int> perm(n);  // target k is source perm[k]
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    Eigen::MatrixXd cen_q(n, 3);
    std::vector<std::string> labels_q;
    std::vector<int> truth(n);
    for (int k = 0; k < n; ++k) {
      cen_q.row(k) = (motion * Eigen::Vector3d(room.centroids.row(perm[k]))).transpose();
      labels_q.push_back(room.labels[perm[k]]);
      truth[perm[k]] = k;
    }
    const Eigen::MatrixXd sem_q = OneHot(labels_q, vocab);
    const Eigen::MatrixXd wp = BuildAffinityMatrix(room.centroids, sem_p);
    const Eigen::MatrixXd wq = BuildAffinityMatrix(cen_q, sem_q);
    const Eigen::MatrixXd c = NodeSimilarity(sem_p, sem_q);
    ObjectMatchConfig cfg;

    // Node similarity is blind to which chair is which: every permutation of the chairs scores
    // the same, while the graph objective prefers the true chairs strictly.
    std::vector<int> chairs{1, 2, 3, 4};
    const double true_score = GraphMatchScore(wp, wq, c, truth, cfg);
    while (std::next_permutation(chairs.begin(), chairs.end())) {
      std::vector<int> swapped = truth;
      for (int i = 0; i < 4; ++i) swapped[1 + i] = truth[chairs[i]];
      const double node_true = (c.cwiseProduct(AssignmentMatrix(truth, n))).sum();
      const double node_swapped = (c.cwiseProduct(AssignmentMatrix(swapped, n))).sum();
      EXPECT_EQ(node_true, node_swapped);
      EXPECT_LT(GraphMatchScore(wp, wq, c, swapped, cfg), true_score - 1.0) << seed;
    }

    cfg.solver = ObjectMatchSolver::kNodeOnly;
    const ObjectMatchResult node_only = MatchObjects(wp, wq, c, cfg);
    int node_only_chairs = 0;
    for (int j = 1; j <= 4; ++j) node_only_chairs += node_only.source_to_target[j] == truth[j];
    node_only_wrong_runs += node_only_chairs < 4;
    // Labels alone are right (it is a label-consistent assignment), chairs are a coin toss.
    EXPECT_TRUE(DropLabelMismatches(node_only.pairs, room.labels, labels_q).size() == 9u);

    for (ObjectMatchSolver solver : {ObjectMatchSolver::kExact, ObjectMatchSolver::kApproximate}) {
      cfg.solver = solver;
      const ObjectMatchResult graph = MatchObjects(wp, wq, c, cfg);
      EXPECT_EQ(graph.source_to_target, truth) << ToString(solver) << " seed " << seed;
    }
  }
  std::printf("  node-only matching confused the chairs in %d of 8 shuffles\n",
              node_only_wrong_runs);
  EXPECT_GT(node_only_wrong_runs, 0);
}

TEST(GraphMatch, UnmatchedObjectsStayUnmatched) {
  // Source: the chair room. Target: the same room without the tv, plus an unrelated object far
  // away. The tv has no counterpart and the far object's only possible partner is of another class.
  const ChairRoom room = MakeChairRoom();
  const std::vector<std::string> vocab{"table", "chair", "lamp", "plant", "tv", "bin", "sink"};
  std::vector<std::string> labels_q;
  Eigen::MatrixXd cen_q(9, 3);
  int k = 0;
  std::vector<int> truth(9, -1);
  for (int j = 0; j < 9; ++j) {
    if (room.labels[j] == "tv") continue;
    cen_q.row(k) = room.centroids.row(j);
    labels_q.push_back(room.labels[j]);
    truth[j] = k++;
  }
  cen_q.row(k) << 0.3, -9.0, 0.5;  // beyond chair 4, on the side away from where the tv was
  labels_q.push_back("sink");
  const Eigen::MatrixXd sem_p = OneHot(room.labels, vocab), sem_q = OneHot(labels_q, vocab);
  const Eigen::MatrixXd wp = BuildAffinityMatrix(room.centroids, sem_p);
  const Eigen::MatrixXd wq = BuildAffinityMatrix(cen_q, sem_q);
  const Eigen::MatrixXd c = NodeSimilarity(sem_p, sem_q);
  for (ObjectMatchSolver solver : {ObjectMatchSolver::kApproximate, ObjectMatchSolver::kNodeOnly}) {
    ObjectMatchConfig cfg;
    cfg.solver = solver;
    const ObjectMatchResult r = MatchObjects(wp, wq, c, cfg);
    EXPECT_EQ(r.source_to_target[7], -1) << ToString(solver);  // the tv
    if (solver != ObjectMatchSolver::kNodeOnly) {
      EXPECT_EQ(r.source_to_target, truth);
    }
  }
}

TEST(GraphMatch, LabelMaskAndPostFilter) {
  const std::vector<std::string> lp{"chair", "table", "lamp"}, lq{"table", "chair", "sofa"};
  const MatchMask mask = LabelCompatibilityMask(lp, lq);
  MatchMask expected(3, 3);
  expected << false, true, false, true, false, false, false, false, false;
  EXPECT_TRUE((mask == expected).all());

  const std::vector<ObjectPair> pairs{{0, 1, 2.0}, {1, 2, 1.5}, {2, 0, 1.2}};
  const std::vector<ObjectPair> kept = DropLabelMismatches(pairs, lp, lq);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].source, 0);
  EXPECT_EQ(kept[0].target, 1);
  EXPECT_THROW(DropLabelMismatches({{3, 0, 1.0}}, lp, lq), InputError);

  // The solvers never return a masked pair, even when the graphs would prefer it.
  std::mt19937_64 rng(2);
  for (ObjectMatchSolver solver :
       {ObjectMatchSolver::kExact, ObjectMatchSolver::kApproximate, ObjectMatchSolver::kNodeOnly}) {
    const Instance in = RandomInstance(3, 3, true, rng);
    ObjectMatchConfig cfg;
    cfg.solver = solver;
    cfg.match_cost = -5.0;  // matching anything is very attractive
    const ObjectMatchResult r = MatchObjects(in.wp, in.wq, in.c, cfg, mask);
    for (const ObjectPair& p : r.pairs) EXPECT_TRUE(mask(p.source, p.target)) << ToString(solver);
  }
}

TEST(GraphMatch, EmptyGraphsAndBadInput) {
  for (ObjectMatchSolver solver :
       {ObjectMatchSolver::kExact, ObjectMatchSolver::kApproximate, ObjectMatchSolver::kNodeOnly}) {
    ObjectMatchConfig cfg;
    cfg.solver = solver;
    const ObjectMatchResult r = MatchObjects(Eigen::MatrixXd(0, 0), Eigen::MatrixXd::Zero(3, 3),
                                             Eigen::MatrixXd(0, 3), cfg);
    EXPECT_TRUE(r.pairs.empty());
    const ObjectMatchResult r2 = MatchObjects(Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd(0, 0),
                                              Eigen::MatrixXd(2, 0), cfg);
    EXPECT_EQ(r2.source_to_target, (std::vector<int>{-1, -1}));
  }
  EXPECT_THROW(MatchObjects(Eigen::MatrixXd::Zero(2, 3), Eigen::MatrixXd::Zero(2, 2),
                            Eigen::MatrixXd::Zero(2, 2)),
               InputError);
  EXPECT_THROW(MatchObjects(Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2),
                            Eigen::MatrixXd::Zero(2, 3)),
               InputError);
}

}  // namespace
}  // namespace zeroreg
