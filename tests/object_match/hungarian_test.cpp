#include "object_match/hungarian.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937_64& rng, double lo, double hi) {
  Eigen::MatrixXd a(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      a(i, j) = lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
    }
  }
  return a;
}

// Minimum over all injections of min(rows, cols) pairs, by enumerating column permutations.
double BruteForceMinCost(const Eigen::MatrixXd& a) {
  const bool t = a.rows() > a.cols();
  const Eigen::MatrixXd c = t ? Eigen::MatrixXd(a.transpose()) : a;
  std::vector<int> cols(static_cast<std::size_t>(c.cols()));
  std::iota(cols.begin(), cols.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    double s = 0;
    for (int i = 0; i < c.rows(); ++i) s += c(i, cols[i]);
    best = std::min(best, s);
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}

// Maximum over all partial injections (any subset of one-to-one pairs) of the summed score.
void BrutePartial(const Eigen::MatrixXd& s, const MatchMask& allowed, int i,
                  std::vector<char>& used, double acc, double& best) {
  if (i == s.rows()) {
    best = std::max(best, acc);
    return;
  }
  BrutePartial(s, allowed, i + 1, used, acc, best);
  for (int k = 0; k < s.cols(); ++k) {
    if (used[k] || !allowed(i, k)) continue;
    used[k] = 1;
    BrutePartial(s, allowed, i + 1, used, acc + s(i, k), best);
    used[k] = 0;
  }
}

double AssignmentValue(const Eigen::MatrixXd& a, const std::vector<int>& row_to_col) {
  double s = 0;
  std::vector<int> seen;
  for (std::size_t i = 0; i < row_to_col.size(); ++i) {
    if (row_to_col[i] < 0) continue;
    seen.push_back(row_to_col[i]);
    s += a(static_cast<Eigen::Index>(i), row_to_col[i]);
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_TRUE(std::adjacent_find(seen.begin(), seen.end()) == seen.end()) << "not one-to-one";
  return s;
}

TEST(Hungarian, EqualsBruteForceOnRandomRectangularMatrices) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 1 + static_cast<int>(rng() % 7);
    const int cols = 1 + static_cast<int>(rng() % 7);
    // Integer-valued costs in half the trials, so that ties are common.
    Eigen::MatrixXd a = RandomMatrix(rows, cols, rng, -5, 5);
    if (trial % 2 == 0) a = a.array().round();
    const std::vector<int> assignment = SolveAssignmentMin(a);
    ASSERT_EQ(static_cast<int>(assignment.size()), rows);
    const int assigned = static_cast<int>(
        std::count_if(assignment.begin(), assignment.end(), [](int c) { return c >= 0; }));
    EXPECT_EQ(assigned, std::min(rows, cols));
    EXPECT_NEAR(AssignmentValue(a, assignment), BruteForceMinCost(a), 1e-9)
        << "trial " << trial << "\n"
        << a;
    EXPECT_NEAR(AssignmentValue(a, SolveAssignmentMax(a)), -BruteForceMinCost(-a), 1e-9);
  }
}

TEST(Hungarian, PartialAssignmentEqualsBruteForceAndRespectsMask) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 1 + static_cast<int>(rng() % 6);
    const int cols = 1 + static_cast<int>(rng() % 6);
    const Eigen::MatrixXd s = RandomMatrix(rows, cols, rng, -1, 2);
    MatchMask allowed(rows, cols);
    for (int i = 0; i < rows; ++i) {
      for (int k = 0; k < cols; ++k) allowed(i, k) = (rng() % 4) != 0;
    }
    const MatchMask mask = trial % 3 == 0 ? MatchMask::Constant(rows, cols, true) : allowed;
    const std::vector<int> a =
        trial % 3 == 0 ? SolvePartialAssignmentMax(s) : SolvePartialAssignmentMax(s, mask);
    double best = 0;
    std::vector<char> used(static_cast<std::size_t>(cols), 0);
    BrutePartial(s, mask, 0, used, 0.0, best);
    EXPECT_NEAR(AssignmentValue(s, a), best, 1e-9) << "trial " << trial;
    for (int i = 0; i < rows; ++i) {
      if (a[i] < 0) continue;
      EXPECT_TRUE(mask(i, a[i]));
      EXPECT_GT(s(i, a[i]), 0.0);  // a non-positive pair adds nothing and is not reported
    }
  }
}

TEST(Hungarian, HandlesEmptyAndRejectsNonFinite) {
  EXPECT_TRUE(SolveAssignmentMin(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(SolveAssignmentMin(Eigen::MatrixXd(2, 0)), (std::vector<int>{-1, -1}));
  Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(2, 2);
  bad(0, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SolveAssignmentMin(bad), InputError);
  EXPECT_THROW(SolvePartialAssignmentMax(Eigen::MatrixXd::Zero(2, 2), MatchMask(3, 2)), InputError);
}

}  // namespace
}  // namespace zeroreg
