// Object-level matching as graph matching (paper §3.3, Eq. 2), Eigen only.
//
// Eq. 2 as printed, min_X ||W^p - X W^q X^T||_F^2 - tr(C X) with X in {0,1}^{n x m},
// X 1_n = 1_m, X^T 1_n <= 1_n, has dimension typos (C X is only defined for n = m; X 1_n needs
// X to have n columns) and, read literally, forces every source object to be matched. We solve the
// consistent, partial version (docs/MATCHING.md derives it):
//
//   X in {0,1}^{n x m},  X 1_m <= 1_n,  X^T 1_n <= 1_m   (one-to-one, objects may stay unmatched)
//   minimise  E(X) = ||W^p - X W^q X^T||_F^2 - alpha <C, X> + tau 1^T X 1
//
// i.e. Eq. 2 with tr(C X) read as <C, X> = tr(C^T X), a weight alpha (node_weight) on the node
// term and a cost tau (match_cost) per matched pair. With alpha = 1, tau = 0 it is Eq. 2 exactly.
// Expanding the norm for a partial injection pi (matched set M):
//   ||W^p - X W^q X^T||^2 = ||W^p||^2 - sum_{j,j' in M} (2 W^p_jj' W^q_pi(j)pi(j') -
//   (W^q_pi(j)pi(j'))^2)
// so minimising E is maximising the score
//   J(X) = sum_{j in M} (alpha C_j,pi(j) - tau)
//        + sum_{j,j' in M} (2 W^p_jj' W^q_pi(j)pi(j') - (W^q_pi(j)pi(j'))^2),   E = ||W^p||^2 - J.
// An edge pair contributes at most (W^p_jj')^2 (when the target edge has the same weight), a target
// edge the source does not have costs (W^q)^2, and leaving a node unmatched forfeits its edges:
// matching is rewarded only when the neighbourhoods agree. With the defaults (alpha = tau = 1) the
// unary term alpha C - tau is exactly cos(s^p_j, s^q_k): a match with no structural support is
// worth making only between semantically similar objects.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "object_match/hungarian.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

// "auto", "exact", "approximate", "node_only"; throws InputError for anything else.
ObjectMatchSolver ObjectMatchSolverFromString(const std::string& name);
std::string ToString(ObjectMatchSolver solver);

struct ObjectPair {
  int source = -1;               // row of W^p / C
  int target = -1;               // row of W^q / column of C
  double node_similarity = 0.0;  // C(source, target) = 1 + cos
};

struct ObjectMatchResult {
  std::vector<int> source_to_target;  // size n, -1 = unmatched
  std::vector<ObjectPair> pairs;      // matched pairs in source order
  double score = 0.0;                 // J(X), maximised
  double energy = 0.0;                // E(X) = ||W^p||^2 - J(X), the (generalised) Eq. 2 value
  ObjectMatchSolver solver = ObjectMatchSolver::kAuto;  // the solver that actually ran
  std::uint64_t search_nodes = 0;  // exact: search-tree nodes visited; approximate: FW steps
};

// Number of partial injections from n source to m target nodes, sum_r C(n,r) m!/(m-r)!, saturated
// at UINT64_MAX.
std::uint64_t CountPartialInjections(int n, int m);

// J(X) and E(X) above for a given assignment (source_to_target: size n, entries in [-1, m)).
double GraphMatchScore(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                       const Eigen::MatrixXd& C, const std::vector<int>& source_to_target,
                       const ObjectMatchConfig& config = {});
double GraphMatchEnergy(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                        const Eigen::MatrixXd& C, const std::vector<int>& source_to_target,
                        const ObjectMatchConfig& config = {});

// Solves Eq. 2 (generalised as above) with config.solver. W_p: n x n, W_q: m x m, C: n x m,
// allowed: empty or n x m (pairs that may match, e.g. LabelCompatibilityMask). Throws InputError
// for wrong sizes or non-finite values.
// `seed`: the approximate solver's random starts (PipelineConfig::seed).
ObjectMatchResult MatchObjects(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                               const Eigen::MatrixXd& C, const ObjectMatchConfig& config = {},
                               const MatchMask& allowed = MatchMask(), std::uint64_t seed = 0);

// The individual solvers (MatchObjects dispatches to these).
ObjectMatchResult MatchObjectsExact(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                    const Eigen::MatrixXd& C, const ObjectMatchConfig& config = {},
                                    const MatchMask& allowed = MatchMask());
ObjectMatchResult MatchObjectsApproximate(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                          const Eigen::MatrixXd& C,
                                          const ObjectMatchConfig& config = {},
                                          const MatchMask& allowed = MatchMask(),
                                          std::uint64_t seed = 0);
// Ablation "without scene graph": the graphs are ignored (score and energy are still reported with
// the full objective, for comparison), X maximises sum (alpha C - tau) over partial assignments.
ObjectMatchResult MatchObjectsNodeOnly(const Eigen::MatrixXd& W_p, const Eigen::MatrixXd& W_q,
                                       const Eigen::MatrixXd& C,
                                       const ObjectMatchConfig& config = {},
                                       const MatchMask& allowed = MatchMask());

// allowed(j, k) = (labels_source[j] == labels_target[k]): the paper's label filter used as a
// constraint during the solve.
MatchMask LabelCompatibilityMask(const std::vector<std::string>& labels_source,
                                 const std::vector<std::string>& labels_target);

// The paper's post-filter (§3.3): keeps the pairs whose category labels are equal. Throws
// InputError when a pair indexes outside the label lists.
std::vector<ObjectPair> DropLabelMismatches(const std::vector<ObjectPair>& pairs,
                                            const std::vector<std::string>& labels_source,
                                            const std::vector<std::string>& labels_target);

}  // namespace zeroreg
