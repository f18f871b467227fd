// Point-level matching with a dustbin and Sinkhorn (paper §3.4, Eq. 3-4), Eigen only.
//
//   S  = G_P G_Q^T                                    (Eq. 3, n x m, cosine for unit descriptors)
//   S' = [[S / T, z 1], [z 1^T, z]]                   (Eq. 4, (n+1) x (m+1), logits)
//   P  = argmax_{P >= 0, P 1 = a, P^T 1 = b} <P, S'> + H(P), solved in the log domain,
//        a = [1 .. 1, m],  b = [1 .. 1, n]            (SuperGlue's marginals)
// Each real point carries unit mass and may send it to a real point of the other set or to the
// dustbin; the source dustbin row can take up to all m target points and the target dustbin column
// up to all n source points, so both sides carry n + m in total and the problem is always
// feasible. A real row of P then sums to 1, so P_ij is "the probability that source i matches
// target j". See docs/MATCHING.md.
#pragma once

#include <Eigen/Core>

#include <vector>
#include "zeroreg/config.hpp"

namespace zeroreg {

struct SinkhornMatch {
  int source = -1;           // row of G_P
  int target = -1;           // row of G_Q
  double probability = 0.0;  // P_ij = exp(log P_ij)
};

// log P ((n+1) x (m+1), last row/column = dustbins) for a raw score matrix S (n x m, Eq. 3), with
// the log-domain iterations u = log a - LSE_row(S' + v), v = log b - LSE_col(S' + u) (log-sum-exp,
// so scores of any magnitude are safe). n = 0 or m = 0 give the trivial plan (all mass to the
// dustbin; -inf where there is none). Throws InputError for non-finite S, temperature <= 0 or
// iterations < 0.
Eigen::MatrixXd SinkhornLogAssignment(const Eigen::MatrixXd& scores,
                                      const SinkhornConfig& config = {});

// Matches read from log P: best real target of each real source (and mutual best when
// config.mutual) with probability >= config.min_probability, in source order.
std::vector<SinkhornMatch> ExtractSinkhornMatches(const Eigen::MatrixXd& log_assignment,
                                                  const SinkhornConfig& config = {});

// The whole §3.4 step: S = G_P G_Q^T (Eq. 3), dustbin augmentation (Eq. 4), Sinkhorn, drop the
// dustbin, extract matches. Rows of G_P (n x d) and G_Q (m x d) are L2-normalised descriptors.
// Throws InputError when the descriptor dimensions differ (and neither set is empty) or values
// are not finite. log_assignment, when not null, receives log P.
std::vector<SinkhornMatch> MatchSinkhorn(const Eigen::MatrixXd& descriptors_source,
                                         const Eigen::MatrixXd& descriptors_target,
                                         const SinkhornConfig& config = {},
                                         Eigen::MatrixXd* log_assignment = nullptr);
// Float descriptors (whole images) run in single precision without log P when log_assignment is
// null, on up to `threads` threads; the matches are the same whatever the thread count.
std::vector<SinkhornMatch> MatchSinkhorn(const Eigen::MatrixXf& descriptors_source,
                                         const Eigen::MatrixXf& descriptors_target,
                                         const SinkhornConfig& config = {},
                                         Eigen::MatrixXd* log_assignment = nullptr,
                                         int threads = 1);

}  // namespace zeroreg
