#include "object_match/graph_match.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

constexpr double kImproveEps = 1e-10;

std::string Dims(Eigen::Index r, Eigen::Index c) {
  return std::to_string(r) + " x " + std::to_string(c);
}

void Validate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q, const Eigen::MatrixXd& C,
              const MatchMask& allowed) {
  if (W_p.rows() != W_p.cols()) {
    throw MakeInputError("W_p", "is " + Dims(W_p.rows(), W_p.cols()) + ", expected square");
  }
  if (W_q.rows() != W_q.cols()) {
    throw MakeInputError("W_q", "is " + Dims(W_q.rows(), W_q.cols()) + ", expected square");
  }
  if (C.rows() != W_p.rows() || C.cols() != W_q.rows()) {
    throw MakeInputError("C", "is " + Dims(C.rows(), C.cols()) +
                                  ", expected n x m = " + Dims(W_p.rows(), W_q.rows()));
  }
  if (allowed.size() != 0 && (allowed.rows() != C.rows() || allowed.cols() != C.cols())) {
    throw MakeInputError("allowed", "is " + Dims(allowed.rows(), allowed.cols()) +
                                        ", expected n x m = " + Dims(C.rows(), C.cols()));
  }
  if (!W_p.allFinite()) throw MakeInputError("W_p", "contains NaN or infinity");
  if (!W_q.allFinite()) throw MakeInputError("W_q", "contains NaN or infinity");
  if (!C.allFinite()) throw MakeInputError("C", "contains NaN or infinity");
}

// The problem in the form the solvers use: J(pi) = sum_j unary(j, pi(j)) + sum_{j<j'} Pair(...).
struct Problem {
  Problem(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q, const Eigen::MatrixXd& C,
          const ObjectMatchConfig& config, const MatchMask& mask)
      : wp(W_p),
        wq(W_q),
        wq2(config.target_edge_weight * W_q.cwiseProduct(W_q)),
        n(static_cast<int>(W_p.rows())),
        m(static_cast<int>(W_q.rows())) {
    Validate(W_p, W_q, C, mask);
    allowed = mask.size() != 0 ? mask : MatchMask::Constant(n, m, true);
    linear = config.node_weight * C.array() - config.match_cost;
    unary = linear;
    // The j = j' terms of the Frobenius expansion (zero for graphs without self-loops).
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < m; ++k) unary(j, k) += 2.0 * wp(j, j) * wq(k, k) - wq2(k, k);
    }
  }

  // Contribution of the two matches j -> k and j2 -> k2 (j != j2, k != k2), both edge directions.
  double Pair(int j, int k, int j2, int k2) const {
    return 2.0 * wp(j, j2) * wq(k, k2) - wq2(k, k2) + 2.0 * wp(j2, j) * wq(k2, k) - wq2(k2, k);
  }

  // What j -> k adds given the other matches of `a`, ignoring sources j and `skip`.
  double Gain(const std::vector<int>& a, int j, int k, int skip) const {
    if (k < 0) return 0.0;
    double g = unary(j, k);
    for (int j2 = 0; j2 < n; ++j2) {
      if (j2 == j || j2 == skip || a[j2] < 0) continue;
      g += Pair(j, k, j2, a[j2]);
    }
    return g;
  }

  double Score(const std::vector<int>& a) const {
    double s = 0.0;
    for (int j = 0; j < n; ++j) {
      if (a[j] < 0) continue;
      s += unary(j, a[j]);
      for (int j2 = j + 1; j2 < n; ++j2) {
        if (a[j2] >= 0) s += Pair(j, a[j], j2, a[j2]);
      }
    }
    return s;
  }

  const Eigen::MatrixXd& wp;
  const Eigen::MatrixXd& wq;
  Eigen::MatrixXd wq2;
  int n, m;
  MatchMask allowed;
  Eigen::MatrixXd linear;  // alpha C - tau
  Eigen::MatrixXd unary;   // linear + self terms
};

void ValidateAssignment(const std::vector<int>& a, int n, int m) {
  if (static_cast<int>(a.size()) != n) {
    throw MakeInputError("source_to_target", "has " + std::to_string(a.size()) +
                                                 " entries, expected n = " + std::to_string(n));
  }
  std::vector<char> used(static_cast<std::size_t>(m), 0);
  for (int k : a) {
    if (k < -1 || k >= m) {
      throw MakeInputError("source_to_target", "has entry " + std::to_string(k) +
                                                   ", expected -1 or a target in [0, " +
                                                   std::to_string(m) + ")");
    }
    if (k >= 0 && used[k]++) {
      throw MakeInputError("source_to_target",
                           "matches target " + std::to_string(k) + " twice, expected one-to-one");
    }
  }
}

ObjectMatchResult MakeResult(const Problem& p, const Eigen::MatrixXd& C, std::vector<int> a,
                             ObjectMatchSolver solver, std::uint64_t nodes) {
  ObjectMatchResult r;
  r.score = p.Score(a);
  r.energy = p.wp.squaredNorm() - r.score;
  for (int j = 0; j < p.n; ++j) {
    if (a[j] >= 0) r.pairs.push_back({j, a[j], C(j, a[j])});
  }
  r.source_to_target = std::move(a);
  r.solver = solver;
  r.search_nodes = nodes;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Exact: depth-first branch and bound over partial injections.
class BranchAndBound {
 public:
  BranchAndBound(const Problem& p, double beta)
      : p_(p),
        beta_(beta),
        lo_(std::min(0.0, p.m > 0 ? p.wq.minCoeff() : 0.0)),
        hi_(std::max(0.0, p.m > 0 ? p.wq.maxCoeff() : 0.0)),
        current_(p.n, -1),
        used_(p.m, 0) {
    // Most connected sources first: their choices constrain the score most, so bounds bite early.
    order_.resize(p.n);
    std::iota(order_.begin(), order_.end(), 0);
    std::vector<double> degree(p.n);
    for (int j = 0; j < p.n; ++j) degree[j] = p.wp.row(j).sum() + p.wp.col(j).sum();
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return degree[a] > degree[b]; });
    // bound_[d]: upper bound on what sources order_[d..] can still add. A source adds at most
    // max(0, best unary) plus, per pair with an earlier source and per edge direction,
    // max_x (2 a x - beta x^2) = a^2 / beta when beta > 0 and x can reach a / beta.
    bound_.assign(p.n + 1, 0.0);
    for (int d = p.n - 1; d >= 0; --d) {
      const int j = order_[d];
      double best_unary = 0.0;
      for (int k = 0; k < p.m; ++k) {
        if (p.allowed(j, k)) best_unary = std::max(best_unary, p.unary(j, k));
      }
      double pairs = 0.0;
      for (int e = 0; e < d; ++e) {
        const int j2 = order_[e];
        pairs += PairBound(p.wp(j, j2)) + PairBound(p.wp(j2, j));
      }
      bound_[d] = bound_[d + 1] + best_unary + pairs;
    }
    best_ = current_;
    best_score_ = 0.0;  // the empty assignment
  }

  // max over x in [lo, hi] of 2 a x - beta x^2: what one edge direction with source weight a can
  // add for any target edge weight x (x = 0 when the pair is not an edge or not matched).
  double PairBound(double a) const {
    const double x = beta_ > 0.0 ? std::clamp(a / beta_, lo_, hi_) : (a >= 0.0 ? hi_ : lo_);
    return 2.0 * a * x - beta_ * x * x;
  }

  std::vector<int> Solve() {
    Search(0, 0.0);
    return best_;
  }
  std::uint64_t nodes() const { return nodes_; }

 private:
  void Search(int d, double score) {
    ++nodes_;
    if (score > best_score_ + kImproveEps * (1.0 + std::abs(best_score_))) {
      best_score_ = score;
      best_ = current_;
    }
    if (d == p_.n) return;
    if (score + bound_[d] <= best_score_ + kImproveEps * (1.0 + std::abs(best_score_))) return;
    const int j = order_[d];
    // Options: every free allowed target, plus "unmatched" (k = -1, gain 0), best first.
    std::vector<std::pair<double, int>> options;
    options.reserve(p_.m + 1);
    for (int k = 0; k < p_.m; ++k) {
      if (used_[k] || !p_.allowed(j, k)) continue;
      double g = p_.unary(j, k);
      for (int e = 0; e < d; ++e) {
        const int j2 = order_[e];
        if (current_[j2] >= 0) g += p_.Pair(j, k, j2, current_[j2]);
      }
      options.emplace_back(g, k);
    }
    options.emplace_back(0.0, -1);
    std::stable_sort(options.begin(), options.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [gain, k] : options) {
      current_[j] = k;
      if (k >= 0) used_[k] = 1;
      Search(d + 1, score + gain);
      if (k >= 0) used_[k] = 0;
      current_[j] = -1;
    }
  }

  const Problem& p_;
  double beta_, lo_, hi_;  // target-edge weight and the range of W^q (with 0)
  std::vector<int> order_;
  std::vector<double> bound_;
  std::vector<int> current_;
  std::vector<char> used_;
  std::vector<int> best_;
  double best_score_ = 0.0;
  std::uint64_t nodes_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Approximate: Frank-Wolfe on the relaxation over doubly-substochastic matrices (FAQ).

// Uniform double in [0, 1) from the raw 64-bit engine output: identical on every standard library
// (std::uniform_real_distribution is not specified bit-exactly).
double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// F(X) = 2 <W^p, X W^q X^T> - <11^T, X (W^q o W^q) X^T> + <alpha C - tau, X>: J extended to real X.
struct Relaxation {
  explicit Relaxation(const Problem& p) : p_(p), wq2_sym(p.wq2 + p.wq2.transpose()) {}

  Eigen::MatrixXd Gradient(const Eigen::MatrixXd& x) const {
    const Eigen::RowVectorXd col_sums = x.colwise().sum();
    Eigen::MatrixXd g = 2.0 * (p_.wp * x * p_.wq.transpose() + p_.wp.transpose() * x * p_.wq);
    g.rowwise() -= col_sums * wq2_sym;
    g += p_.linear;
    return g;
  }

  // Quadratic part of F evaluated at a direction d: F(X + t d) = F(X) + t <grad, d> + t^2 Q(d).
  double Quadratic(const Eigen::MatrixXd& d) const {
    const Eigen::RowVectorXd cs = d.colwise().sum();
    return 2.0 * p_.wp.cwiseProduct(d * p_.wq * d.transpose()).sum() -
           (cs * p_.wq2 * cs.transpose())(0, 0);
  }

  const Problem& p_;
  Eigen::MatrixXd wq2_sym;
};

Eigen::MatrixXd ToMatrix(const std::vector<int>& a, int m) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(a.size()), m);
  for (std::size_t j = 0; j < a.size(); ++j) {
    if (a[j] >= 0) x(static_cast<Eigen::Index>(j), a[j]) = 1.0;
  }
  return x;
}

// Frank-Wolfe: the linear oracle over the doubly-substochastic polytope (the real block of the
// doubly-stochastic polytope padded with n + m dummy nodes) is a partial assignment maximising
// <grad, Y>, i.e. Hungarian with a zero-score dummy per row. Exact line search on the quadratic.
Eigen::MatrixXd FrankWolfe(const Relaxation& rel, const Problem& p, Eigen::MatrixXd x,
                           int iterations, std::uint64_t* steps) {
  for (int it = 0; it < iterations; ++it) {
    ++*steps;
    const Eigen::MatrixXd g = rel.Gradient(x);
    const Eigen::MatrixXd d = ToMatrix(SolvePartialAssignmentMax(g, p.allowed), p.m) - x;
    const double slope = g.cwiseProduct(d).sum();  // Frank-Wolfe gap
    if (slope <= 1e-9) break;
    const double q = rel.Quadratic(d);
    const double t = q < 0.0 ? std::min(1.0, -slope / (2.0 * q)) : 1.0;
    x += t * d;
  }
  return x;
}

// Nearest partial assignment to a relaxed X: maximise sum over matched X_jk plus, for an unmatched
// source, its dummy mass 1 - sum_k X_jk. Subtracting that constant per row gives a partial
// assignment problem on X_jk - (1 - rowsum_j).
std::vector<int> Project(const Eigen::MatrixXd& x, const MatchMask& allowed) {
  Eigen::MatrixXd s = x;
  const Eigen::VectorXd dummy = 1.0 - x.rowwise().sum().array();
  s.colwise() -= dummy;
  return SolvePartialAssignmentMax(s, allowed);
}

// First-improvement local search on the discrete score: move one source to a free target or to
// unmatched, or swap the targets of two sources. O(n^2 m + n^3) per pass.
void LocalSearch(const Problem& p, std::vector<int>& a) {
  std::vector<int> owner(p.m, -1);
  for (int j = 0; j < p.n; ++j) {
    if (a[j] >= 0) owner[a[j]] = j;
  }
  auto pair_or_zero = [&](int j, int k, int j2, int k2) {
    return (k < 0 || k2 < 0) ? 0.0 : p.Pair(j, k, j2, k2);
  };
  bool improved = true;
  for (int pass = 0; improved && pass < 100; ++pass) {
    improved = false;
    for (int j = 0; j < p.n; ++j) {
      const int k = a[j];
      const double current = p.Gain(a, j, k, -1);
      double best_delta = kImproveEps;
      int best_k = k;
      for (int k2 = -1; k2 < p.m; ++k2) {
        if (k2 == k || (k2 >= 0 && (owner[k2] >= 0 || !p.allowed(j, k2)))) continue;
        const double delta = p.Gain(a, j, k2, -1) - current;
        if (delta > best_delta) {
          best_delta = delta;
          best_k = k2;
        }
      }
      if (best_k != k) {
        if (k >= 0) owner[k] = -1;
        if (best_k >= 0) owner[best_k] = j;
        a[j] = best_k;
        improved = true;
      }
      for (int j2 = 0; j2 < p.n; ++j2) {
        const int kj = a[j];
        const int k2 = a[j2];
        if (j2 == j || k2 == kj) continue;
        if ((k2 >= 0 && !p.allowed(j, k2)) || (kj >= 0 && !p.allowed(j2, kj))) continue;
        const double before =
            p.Gain(a, j, kj, j2) + p.Gain(a, j2, k2, j) + pair_or_zero(j, kj, j2, k2);
        const double after =
            p.Gain(a, j, k2, j2) + p.Gain(a, j2, kj, j) + pair_or_zero(j, k2, j2, kj);
        if (after - before > kImproveEps) {
          a[j] = k2;
          a[j2] = kj;
          if (k2 >= 0) owner[k2] = j;
          if (kj >= 0) owner[kj] = j2;
          improved = true;
        }
      }
    }
  }
}

}  // namespace

ObjectMatchSolver ObjectMatchSolverFromString(const std::string& name) {
  if (name == "auto") return ObjectMatchSolver::kAuto;
  if (name == "exact") return ObjectMatchSolver::kExact;
  if (name == "approximate") return ObjectMatchSolver::kApproximate;
  if (name == "node_only") return ObjectMatchSolver::kNodeOnly;
  throw MakeInputError("object match solver",
                       "is \"" + name + "\", expected auto, exact, approximate or node_only");
}

std::string ToString(ObjectMatchSolver solver) {
  switch (solver) {
    case ObjectMatchSolver::kAuto:
      return "auto";
    case ObjectMatchSolver::kExact:
      return "exact";
    case ObjectMatchSolver::kApproximate:
      return "approximate";
    case ObjectMatchSolver::kNodeOnly:
      return "node_only";
  }
  return "unknown";
}

std::uint64_t CountPartialInjections(int n, int m) {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  if (n < 0 || m < 0) return 0;
  std::uint64_t total = 0;
  std::uint64_t binom = 1;  // C(n, r)
  std::uint64_t perm = 1;   // m! / (m - r)!
  bool binom_saturated = false, perm_saturated = false;
  for (int r = 0; r <= std::min(n, m); ++r) {
    if (r > 0) {
      // C(n, r) = C(n, r-1) (n - r + 1) / r; the product is divisible by r.
      std::uint64_t next;
      if (binom_saturated ||
          __builtin_mul_overflow(binom, static_cast<std::uint64_t>(n - r + 1), &next)) {
        binom_saturated = true;
      } else {
        binom = next / static_cast<std::uint64_t>(r);
      }
      if (perm_saturated ||
          __builtin_mul_overflow(perm, static_cast<std::uint64_t>(m - r + 1), &perm)) {
        perm_saturated = true;
      }
    }
    std::uint64_t term;
    if (binom_saturated || perm_saturated || __builtin_mul_overflow(binom, perm, &term) ||
        __builtin_add_overflow(total, term, &total)) {
      return kMax;
    }
  }
  return total;
}

double GraphMatchScore(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                       const Eigen::MatrixXd& C, const std::vector<int>& source_to_target,
                       const ObjectMatchConfig& config) {
  const Problem p(W_p, W_q, C, config, MatchMask());
  ValidateAssignment(source_to_target, p.n, p.m);
  return p.Score(source_to_target);
}

double GraphMatchEnergy(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                        const Eigen::MatrixXd& C, const std::vector<int>& source_to_target,
                        const ObjectMatchConfig& config) {
  return W_p.squaredNorm() - GraphMatchScore(W_p, W_q, C, source_to_target, config);
}

ObjectMatchResult MatchObjectsExact(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                    const Eigen::MatrixXd& C, const ObjectMatchConfig& config,
                                    const MatchMask& allowed) {
  const Problem p(W_p, W_q, C, config, allowed);
  BranchAndBound bnb(p, config.target_edge_weight);
  std::vector<int> a = bnb.Solve();
  return MakeResult(p, C, std::move(a), ObjectMatchSolver::kExact, bnb.nodes());
}

ObjectMatchResult MatchObjectsApproximate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                          const Eigen::MatrixXd& C, const ObjectMatchConfig& config,
                                          const MatchMask& allowed, std::uint64_t seed) {
  const Problem p(W_p, W_q, C, config, allowed);
  if (p.n == 0 || p.m == 0) {
    return MakeResult(p, C, std::vector<int>(p.n, -1), ObjectMatchSolver::kApproximate, 0);
  }
  const Relaxation rel(p);
  std::mt19937_64 rng(seed);
  const Eigen::MatrixXd mask = p.allowed.cast<double>();
  // Barycentre of the padded (n + m) x (n + m) doubly-stochastic polytope, restricted to the
  // allowed pairs (still doubly substochastic).
  const Eigen::MatrixXd barycentre = mask / static_cast<double>(p.n + p.m);
  std::vector<int> best;
  double best_score = 0.0;
  std::uint64_t steps = 0;
  const int starts = std::max(1, config.restarts);
  for (int s = 0; s < starts; ++s) {
    Eigen::MatrixXd x0;
    if (s == 0) {
      x0 = barycentre;
    } else if (s == 1) {
      x0 = ToMatrix(SolvePartialAssignmentMax(p.linear, p.allowed), p.m);
    } else {
      Eigen::MatrixXd r(p.n, p.m);
      for (Eigen::Index j = 0; j < r.rows(); ++j) {
        for (Eigen::Index k = 0; k < r.cols(); ++k) r(j, k) = Uniform01(rng);
      }
      r = r.cwiseProduct(mask);
      const double scale =
          std::max({r.rowwise().sum().maxCoeff(), r.colwise().sum().maxCoeff(), 1e-12});
      x0 = 0.5 * barycentre + 0.5 * r / scale;
    }
    const Eigen::MatrixXd x = FrankWolfe(rel, p, x0, config.iterations, &steps);
    std::vector<int> a = Project(x, p.allowed);
    LocalSearch(p, a);
    const double score = p.Score(a);
    if (best.empty() || score > best_score + kImproveEps * (1.0 + std::abs(best_score))) {
      best_score = score;
      best = std::move(a);
    }
  }
  return MakeResult(p, C, std::move(best), ObjectMatchSolver::kApproximate, steps);
}

ObjectMatchResult MatchObjectsNodeOnly(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                       const Eigen::MatrixXd& C, const ObjectMatchConfig& config,
                                       const MatchMask& allowed) {
  const Problem p(W_p, W_q, C, config, allowed);
  std::vector<int> a = SolvePartialAssignmentMax(p.linear, p.allowed);
  return MakeResult(p, C, std::move(a), ObjectMatchSolver::kNodeOnly, 0);
}

ObjectMatchResult MatchObjects(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                               const Eigen::MatrixXd& C, const ObjectMatchConfig& config,
                               const MatchMask& allowed, std::uint64_t seed) {
  switch (config.solver) {
    case ObjectMatchSolver::kExact:
      return MatchObjectsExact(W_p, W_q, C, config, allowed);
    case ObjectMatchSolver::kApproximate:
      return MatchObjectsApproximate(W_p, W_q, C, config, allowed, seed);
    case ObjectMatchSolver::kNodeOnly:
      return MatchObjectsNodeOnly(W_p, W_q, C, config, allowed);
    case ObjectMatchSolver::kAuto:
      break;
  }
  const std::uint64_t count =
      CountPartialInjections(static_cast<int>(W_p.rows()), static_cast<int>(W_q.rows()));
  if (count <= config.max_exact_assignments) return MatchObjectsExact(W_p, W_q, C, config, allowed);
  return MatchObjectsApproximate(W_p, W_q, C, config, allowed, seed);
}

MatchMask LabelCompatibilityMask(const std::vector<std::string>& labels_source,
                                 const std::vector<std::string>& labels_target) {
  MatchMask mask(static_cast<Eigen::Index>(labels_source.size()),
                 static_cast<Eigen::Index>(labels_target.size()));
  for (std::size_t j = 0; j < labels_source.size(); ++j) {
    for (std::size_t k = 0; k < labels_target.size(); ++k) {
      mask(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k)) =
          labels_source[j] == labels_target[k];
    }
  }
  return mask;
}

std::vector<ObjectPair> DropLabelMismatches(const std::vector<ObjectPair>& pairs,
                                            const std::vector<std::string>& labels_source,
                                            const std::vector<std::string>& labels_target) {
  std::vector<ObjectPair> kept;
  for (const ObjectPair& pair : pairs) {
    if (pair.source < 0 || pair.source >= static_cast<int>(labels_source.size()) ||
        pair.target < 0 || pair.target >= static_cast<int>(labels_target.size())) {
      throw MakeInputError("object pair", "(" + std::to_string(pair.source) + ", " +
                                              std::to_string(pair.target) +
                                              ") is outside the label lists (" +
                                              std::to_string(labels_source.size()) + " source, " +
                                              std::to_string(labels_target.size()) + " target)");
    }
    if (labels_source[pair.source] == labels_target[pair.target]) kept.push_back(pair);
  }
  return kept;
}

}  // namespace zeroreg
