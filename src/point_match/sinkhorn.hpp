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

namespace zeroreg {

struct SinkhornConfig {
  int iterations = 20;  // paper: 20 Sinkhorn iterations
  // T, in cosine-similarity units. Dividing S by T turns cosines in [-1, 1] into logits in
  // [-1/T, 1/T]; Sinkhorn on S/T maximises <P, S> + T H(P), so T is the entropic regularisation:
  // small T approaches the hard optimal assignment, large T spreads probability. 0.1 is the usual
  // dual-softmax temperature for L2-normalised descriptors (LoFTR, XFeat's matcher).
  double temperature = 0.1;
  // z of Eq. 4, in logit units, i.e. the dustbin entries are z and NOT divided by T. The paper's
  // z = 1 comes from SuperGlue, where the bin score is a logit compared with unnormalised scores.
  // Read on the raw cosine scale (z / T = 10) the dustbin would tie with a perfect match (cos = 1)
  // and take about half of every point's mass; in logit units a match competes with the dustbin
  // once its cosine exceeds z * T = 0.1.
  double dustbin_score = 1.0;
  // A match is kept when P_ij is at least this (P_ij is a probability: real rows sum to 1).
  double min_probability = 0.2;
  // Keep (i, j) only when j is i's best target and i is j's best source (dustbin excluded from
  // both argmaxes, as in SuperGlue). When false, every source keeps its best target.
  bool mutual = true;
};

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
std::vector<SinkhornMatch> MatchSinkhorn(const Eigen::MatrixXf& descriptors_source,
                                         const Eigen::MatrixXf& descriptors_target,
                                         const SinkhornConfig& config = {},
                                         Eigen::MatrixXd* log_assignment = nullptr);

}  // namespace zeroreg
