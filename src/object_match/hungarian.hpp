// Rectangular linear assignment (Hungarian / Kuhn-Munkres with potentials), own implementation.
//
// Used by the object matchers (§3.3): as the exact solver of the node-only ablation, as the linear
// minimisation oracle of Frank-Wolfe and to project a relaxed solution onto assignments.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace zeroreg {

// Pairs allowed to match (n x m, true = allowed). An empty (0 x 0) mask allows everything.
using MatchMask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;

// Minimum-cost assignment of min(rows, cols) pairs of a rows x cols cost matrix, every row (when
// rows <= cols) or every column (otherwise) assigned exactly once. Returns row -> column, -1 for a
// row left out. O(r^2 c) with r = min(rows, cols), c = max(rows, cols). Throws InputError for
// non-finite costs.
std::vector<int> SolveAssignmentMin(const Eigen::MatrixXd& cost);

// Same, maximising the total score.
std::vector<int> SolveAssignmentMax(const Eigen::MatrixXd& score);

// Maximum-score partial assignment: any subset of one-to-one pairs, so a pair is worth taking only
// when its score is > 0, and pairs forbidden by `allowed` (when not empty) are never taken.
// Solved as a rows x (cols + rows) assignment where each row has a private dummy column of score 0
// (being unmatched); forbidden pairs get a negative score, which the dummy always beats. Pairs
// with score <= 0 are removed from the result (they add nothing). Returns row -> column or -1.
std::vector<int> SolvePartialAssignmentMax(const Eigen::MatrixXd& score,
                                           const MatchMask& allowed = MatchMask());

}  // namespace zeroreg
