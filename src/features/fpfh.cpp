#include "features/fpfh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "parallel/parallel_for.hpp"

namespace zeroreg {

FpfhCloud ComputeFpfh(const std::vector<Eigen::Vector3d>& points, const FpfhParams& p) {
  FpfhCloud out;
  open3d_module::Module().compute_fpfh(points, p, &out);
  return out;
}

namespace {

// The two closest target features of one source feature, by squared distance; offered in index
// order, ties keep the earlier.
struct ClosestTwo {
  double d1 = std::numeric_limits<double>::infinity();
  double d2 = std::numeric_limits<double>::infinity();
  int t1 = -1;

  void Offer(double d, int t) {
    if (d < d1) {
      d2 = d1;
      d1 = d;
      t1 = t;
    } else if (d < d2) {
      d2 = d;
    }
  }
};

// The closest source feature of one target feature.
struct Closest {
  double d = std::numeric_limits<double>::infinity();
  int s = -1;
};

// Source features per block of the distance matrix: 256 x a few thousand targets is a few MB.
constexpr Eigen::Index kSourceBlock = 256;

// The squared distance by definition, summed in dimension order: what every comparison below is
// made on, so that the pairs do not depend on how the matrix product rounds.
double SquaredDistance(const Eigen::MatrixXd& S, Eigen::Index s, const Eigen::MatrixXd& T,
                       Eigen::Index t) {
  double sum = 0;
  for (Eigen::Index k = 0; k < S.rows(); ++k) {
    const double d = S(k, s) - T(k, t);
    sum += d * d;
  }
  return sum;
}

}  // namespace

// Brute force instead of a k-d tree: in 33 dimensions a k-d tree visits most of its leaves
// (Open3D's KDTreeFlann took ~0.7 s of a 3DLoMatch pair's geometry hypothesis, ~5k x 5k features),
// while the distance matrix is mostly one matrix product, |s|^2 + |t|^2 - 2 s.t, in row blocks.
// The product only screens: wherever it cannot rule an entry out of a row's best two or a
// column's best, the distance is computed by definition, and only those entries compete.
std::vector<FeaturePair> MutualFeatureMatches(const FpfhCloud& source, const FpfhCloud& target,
                                              int threads) {
  std::vector<FeaturePair> out;
  const Eigen::MatrixXd& S = source.features;  // dims x ns
  const Eigen::MatrixXd& T = target.features;  // dims x nt
  const Eigen::Index ns = S.cols(), nt = T.cols();
  if (ns < 2 || nt < 2 || S.rows() != T.rows()) return out;
  const Eigen::VectorXd s_norm = S.colwise().squaredNorm().transpose();
  const Eigen::RowVectorXd t_norm = T.colwise().squaredNorm();
  // A bound on the expansion's rounding error (a dot product of n terms is off by at most about
  // n eps |s| |t| <= n eps (|s|^2 + |t|^2) / 2), with a wide margin.
  const double slack = 64.0 * static_cast<double>(S.rows() + 2) *
                       std::numeric_limits<double>::epsilon() *
                       (s_norm.maxCoeff() + t_norm.maxCoeff());
  const Eigen::Index blocks = (ns + kSourceBlock - 1) / kSourceBlock;
  std::vector<ClosestTwo> forward(static_cast<size_t>(ns));
  // Per block, each target's closest source in that block; merged in block order below, so that
  // the result (ties to the lowest index) does not depend on the thread count.
  std::vector<std::vector<Closest>> backward(static_cast<size_t>(blocks));
  ParallelFor(
      static_cast<size_t>(blocks), threads,
      [&](size_t begin, size_t end) {
        Eigen::MatrixXd d2;
        std::vector<ClosestTwo> row_screen;
        Eigen::RowVectorXd column_first;
        for (size_t b = begin; b < end; ++b) {
          const Eigen::Index first = static_cast<Eigen::Index>(b) * kSourceBlock;
          const Eigen::Index rows = std::min(kSourceBlock, ns - first);
          const auto block = S.middleCols(first, rows);
          d2.noalias() = -2.0 * block.transpose() * T;
          d2.colwise() += s_norm.segment(first, rows);
          d2.rowwise() += t_norm;
          // The screen: each row's two smallest and each column's smallest approximate values.
          row_screen.assign(static_cast<size_t>(rows), ClosestTwo{});
          column_first = d2.colwise().minCoeff();
          for (Eigen::Index c = 0; c < nt; ++c) {
            for (Eigen::Index r = 0; r < rows; ++r) {
              row_screen[static_cast<size_t>(r)].Offer(d2(r, c), static_cast<int>(c));
            }
          }
          std::vector<Closest>& back = backward[b];
          back.assign(static_cast<size_t>(nt), Closest{});
          for (Eigen::Index c = 0; c < nt; ++c) {
            for (Eigen::Index r = 0; r < rows; ++r) {
              const double approx = d2(r, c);
              if (approx > row_screen[static_cast<size_t>(r)].d2 + 2 * slack &&
                  approx > column_first[c] + 2 * slack) {
                continue;  // exactly farther than the row's best two and the column's best
              }
              const double d = SquaredDistance(S, first + r, T, c);
              forward[static_cast<size_t>(first + r)].Offer(d, static_cast<int>(c));
              Closest& k = back[static_cast<size_t>(c)];
              if (d < k.d) k = Closest{d, static_cast<int>(first + r)};
            }
          }
        }
      },
      /*min_per_thread=*/1);
  std::vector<Closest> closest_source(static_cast<size_t>(nt));
  for (const std::vector<Closest>& back : backward) {
    for (size_t c = 0; c < back.size(); ++c) {
      if (back[c].d < closest_source[c].d) closest_source[c] = back[c];
    }
  }
  for (Eigen::Index s = 0; s < ns; ++s) {
    const ClosestTwo& f = forward[static_cast<size_t>(s)];
    if (f.t1 < 0 || closest_source[static_cast<size_t>(f.t1)].s != static_cast<int>(s)) continue;
    const double d1 = std::sqrt(f.d1), d2 = std::sqrt(f.d2);
    FeaturePair pair;
    pair.source = static_cast<int>(s);
    pair.target = f.t1;
    pair.score = d2 > 0 ? static_cast<float>(1.0 - d1 / d2) : 0.0f;
    out.push_back(pair);
  }
  return out;
}

}  // namespace zeroreg
