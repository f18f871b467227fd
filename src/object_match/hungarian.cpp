#include "object_match/hungarian.hpp"

#include <limits>
#include <string>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Shortest augmenting path with row/column potentials (Kuhn-Munkres, O(n^2 m)) for n <= m.
// Indices are 1-based inside, column 0 is the virtual start of each augmenting path.
std::vector<int> AssignRowsToColumns(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows());
  const int m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);  // p[j]: row assigned to column j (0 = none)
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j) {
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  }
  return row_to_col;
}

}  // namespace

std::vector<int> SolveAssignmentMin(const Eigen::MatrixXd& cost) {
  if (!cost.allFinite()) throw MakeInputError("assignment cost", "contains NaN or infinity");
  const auto rows = static_cast<std::size_t>(cost.rows());
  if (cost.rows() == 0 || cost.cols() == 0) return std::vector<int>(rows, -1);
  if (cost.rows() <= cost.cols()) return AssignRowsToColumns(cost);
  const std::vector<int> col_to_row = AssignRowsToColumns(cost.transpose());
  std::vector<int> row_to_col(rows, -1);
  for (std::size_t c = 0; c < col_to_row.size(); ++c) {
    if (col_to_row[c] >= 0)
      row_to_col[static_cast<std::size_t>(col_to_row[c])] = static_cast<int>(c);
  }
  return row_to_col;
}

std::vector<int> SolveAssignmentMax(const Eigen::MatrixXd& score) {
  return SolveAssignmentMin(-score);
}

std::vector<int> SolvePartialAssignmentMax(const Eigen::MatrixXd& score, const MatchMask& allowed) {
  const Eigen::Index n = score.rows();
  const Eigen::Index m = score.cols();
  const bool masked = allowed.size() != 0;
  if (masked && (allowed.rows() != n || allowed.cols() != m)) {
    throw MakeInputError("allowed mask", "is " + std::to_string(allowed.rows()) + " x " +
                                             std::to_string(allowed.cols()) + ", expected " +
                                             std::to_string(n) + " x " + std::to_string(m));
  }
  if (!score.allFinite()) throw MakeInputError("assignment score", "contains NaN or infinity");
  if (n == 0 || m == 0) return std::vector<int>(static_cast<std::size_t>(n), -1);
  // Any negative score is beaten by the row's private dummy (score 0) without affecting others.
  const double forbidden = -1.0 - score.cwiseAbs().maxCoeff();
  Eigen::MatrixXd padded = Eigen::MatrixXd::Constant(n, m + n, forbidden);
  padded.leftCols(m) = score;
  if (masked) padded.leftCols(m) = allowed.select(score, forbidden);
  for (Eigen::Index i = 0; i < n; ++i) padded(i, m + i) = 0.0;
  std::vector<int> row_to_col = SolveAssignmentMax(padded);
  for (Eigen::Index i = 0; i < n; ++i) {
    int& c = row_to_col[static_cast<std::size_t>(i)];
    if (c >= m || (c >= 0 && score(i, c) <= 0.0) || (c >= 0 && masked && !allowed(i, c))) c = -1;
  }
  return row_to_col;
}

}  // namespace zeroreg
