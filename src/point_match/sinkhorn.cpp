#include "point_match/sinkhorn.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "parallel/parallel_for.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();

// log sum_k exp(M_ik) per row, shifted by the row maximum so that nothing overflows.
Eigen::VectorXd RowLogSumExp(const Eigen::MatrixXd& m) {
  Eigen::VectorXd out(m.rows());
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const double mx = m.row(i).maxCoeff();
    if (!std::isfinite(mx)) {
      out(i) = mx;  // all -inf: no mass can go anywhere
      continue;
    }
    out(i) = mx + std::log((m.row(i).array() - mx).exp().sum());
  }
  return out;
}

// Column blocks of the kernel in SinglePrecisionSinkhorn. Their number is fixed, not the thread
// count: every sum over columns is made per block, in column order, and the blocks' partial sums
// are then added in block order, so the matches are the same whatever the thread count. Four
// blocks give each of up to four threads one.
constexpr std::size_t kColumnBlocks = 4;
// Below this many kernel entries (256 x 256) a thread costs more than it saves (~50 us to start
// one, 20 iterations); the arithmetic is the same either way.
constexpr Eigen::Index kMinEntriesForThreads = Eigen::Index{1} << 16;

// The scaling form of SinkhornLogAssignment for whole images, in single precision and without
// materialising log P: on 4096 x 4096 keypoints the iterations stream the (n+1) x (m+1) kernel
// from memory 2 x 20 times, so halving its size halves the stage, and the matches are read from
// the kernel and the scalings directly (4096 x 4096 random unit descriptors on this 2-core
// machine: 1.1 s in double through log P, 0.38 s here with two passes over K per iteration, the
// same matches). The kernel's column blocks (kColumnBlocks) are shared among `threads`: the
// product, the exp and each iteration's pass over K split, and one pass is bound by memory
// bandwidth per core (4096 x 4096: 0.56 s on one thread, 0.36 s on two). Returns false, leaving
// `matches` alone, when the logits span too wide a range for float (exp underflows below
// ~e^-87), so the caller falls back to double.
bool SinglePrecisionSinkhorn(const Eigen::MatrixXf& descriptors_source,
                             const Eigen::MatrixXf& descriptors_target,
                             const SinkhornConfig& config, int threads,
                             std::vector<SinkhornMatch>* matches) {
  const Eigen::Index n = descriptors_source.rows(), m = descriptors_target.rows();
  if (n * m < kMinEntriesForThreads) threads = 1;
  std::vector<Eigen::Index> block_start(kColumnBlocks + 1);
  for (std::size_t b = 0; b <= kColumnBlocks; ++b) {
    block_start[b] = m * static_cast<Eigen::Index>(b) / static_cast<Eigen::Index>(kColumnBlocks);
  }
  const auto for_each_block = [&](const auto& body) {
    ParallelFor(
        kColumnBlocks, threads,
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t b = begin; b < end; ++b) {
            body(b, block_start[b], block_start[b + 1] - block_start[b]);
          }
        },
        /*min_per_thread=*/1);
  };
  // S (Eq. 3), block by block, with each block's range of scores.
  Eigen::MatrixXf kernel(n, m);
  std::vector<float> block_max(kColumnBlocks, -std::numeric_limits<float>::infinity());
  std::vector<float> block_min(kColumnBlocks, std::numeric_limits<float>::infinity());
  for_each_block([&](std::size_t b, Eigen::Index first, Eigen::Index width) {
    if (width == 0) return;
    auto block = kernel.middleCols(first, width);
    block.noalias() = descriptors_source * descriptors_target.middleRows(first, width).transpose();
    block_max[b] = block.maxCoeff();
    block_min[b] = block.minCoeff();
  });
  const double inv_t = 1.0 / config.temperature;
  const double z_max =
      std::max(static_cast<double>(*std::max_element(block_max.begin(), block_max.end())) * inv_t,
               config.dustbin_score);
  const double z_min =
      std::min(static_cast<double>(*std::min_element(block_min.begin(), block_min.end())) * inv_t,
               config.dustbin_score);
  if (!(z_max - z_min < 80.0)) return false;
  // K = exp(S' - max S') for the real block; every dustbin entry (Eq. 4: the constant z) is
  // the same number k_dust. Each column block also sums its rows: the first K v (v = 1).
  std::vector<Eigen::VectorXf> partial(kColumnBlocks, Eigen::VectorXf::Zero(n));
  for_each_block([&](std::size_t b, Eigen::Index first, Eigen::Index width) {
    for (Eigen::Index j = first; j < first + width; ++j) {
      auto column = kernel.col(j);
      column.array() =
          (column.array() * static_cast<float>(inv_t) - static_cast<float>(z_max)).exp();
      partial[b] += column;
    }
  });
  const auto sum_partials = [&](Eigen::VectorXf* out) {
    *out = partial[0];
    for (std::size_t b = 1; b < kColumnBlocks; ++b) *out += partial[b];
  };
  const double k_dust = std::exp(config.dustbin_score - z_max);
  // Scalings of the real rows / columns and of the two dustbins (marginals as in
  // SinkhornLogAssignment: 1 per real point, m for the source dustbin row, n for the column).
  Eigen::VectorXd u = Eigen::VectorXd::Ones(n), v = Eigen::VectorXd::Ones(m);
  double u_dust = 1.0, v_dust = 1.0;
  // The iterations are bound by reading K from memory (64 MiB at 4096 x 4096), so each reads it
  // once, not twice: walking K's columns, column j gives (K^T u)_j, hence v_j, and at once adds
  // K_j v_j to the K v of the next iteration's u. (Two passes per iteration, one for K v and one
  // for K^T u, took 1.9x as long on this machine; the sums are the same up to float rounding.)
  Eigen::VectorXf kv;
  sum_partials(&kv);
  for (int it = 0; it < config.iterations; ++it) {
    u = (kv.cast<double>().array() + k_dust * v_dust).inverse();
    u_dust = static_cast<double>(m) / (k_dust * (v.sum() + v_dust));
    const Eigen::VectorXf u_float = u.cast<float>();
    const bool last = it + 1 == config.iterations;
    for_each_block([&](std::size_t b, Eigen::Index first, Eigen::Index width) {
      Eigen::VectorXf& next_kv = partial[b];
      next_kv.setZero();
      for (Eigen::Index j = first; j < first + width; ++j) {
        const auto column = kernel.col(j);
        v(j) = 1.0 / (static_cast<double>(column.dot(u_float)) + k_dust * u_dust);
        if (!last) next_kv.noalias() += column * static_cast<float>(v(j));
      }
    });
    v_dust = static_cast<double>(n) / (k_dust * (u.sum() + u_dust));
    if (!last) sum_partials(&kv);
  }
  // P_ij = u_i K_ij v_j. A row's best column maximises K_ij v_j, a column's best row u_i K_ij
  // (dustbins excluded, first index on ties, as ExtractSinkhornMatches): per block, then the
  // blocks in order, keeping the earlier block on ties.
  std::vector<std::vector<double>> block_row_best(kColumnBlocks,
                                                  std::vector<double>(static_cast<std::size_t>(n)));
  std::vector<std::vector<Eigen::Index>> block_row_arg(
      kColumnBlocks, std::vector<Eigen::Index>(static_cast<std::size_t>(n)));
  std::vector<Eigen::Index> col_arg(static_cast<std::size_t>(m), 0);
  for_each_block([&](std::size_t b, Eigen::Index first, Eigen::Index width) {
    std::vector<double>& row_best = block_row_best[b];
    std::vector<Eigen::Index>& row_arg = block_row_arg[b];
    std::fill(row_best.begin(), row_best.end(), -1.0);
    std::fill(row_arg.begin(), row_arg.end(), 0);
    for (Eigen::Index j = first; j < first + width; ++j) {
      const float* column = kernel.col(j).data();
      double col_best = -1.0;
      for (Eigen::Index i = 0; i < n; ++i) {
        const double k = column[i];
        if (k * u(i) > col_best) {
          col_best = k * u(i);
          col_arg[static_cast<std::size_t>(j)] = i;
        }
        if (k * v(j) > row_best[static_cast<std::size_t>(i)]) {
          row_best[static_cast<std::size_t>(i)] = k * v(j);
          row_arg[static_cast<std::size_t>(i)] = j;
        }
      }
    }
  });
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto row = static_cast<std::size_t>(i);
    double best = -1.0;
    Eigen::Index j = 0;
    for (std::size_t b = 0; b < kColumnBlocks; ++b) {
      if (block_row_best[b][row] > best) {
        best = block_row_best[b][row];
        j = block_row_arg[b][row];
      }
    }
    const double probability = u(i) * best;
    if (!(probability >= config.min_probability)) continue;
    if (config.mutual && col_arg[static_cast<std::size_t>(j)] != i) continue;
    matches->push_back({static_cast<int>(i), static_cast<int>(j), probability});
  }
  return true;
}

}  // namespace

Eigen::MatrixXd SinkhornLogAssignment(const Eigen::MatrixXd& scores, const SinkhornConfig& config) {
  if (!(config.temperature > 0.0) || !std::isfinite(config.temperature)) {
    throw MakeInputError("match.sinkhorn.temperature",
                         "is " + std::to_string(config.temperature) + ", expected > 0");
  }
  if (config.iterations < 0) {
    throw MakeInputError("match.sinkhorn.iterations",
                         "is " + std::to_string(config.iterations) + ", expected >= 0");
  }
  if (!std::isfinite(config.dustbin_score)) {
    throw MakeInputError("match.sinkhorn.dustbin_score", "is not finite");
  }
  if (!scores.allFinite()) throw MakeInputError("Sinkhorn scores", "contain NaN or infinity");

  const Eigen::Index n = scores.rows();
  const Eigen::Index m = scores.cols();
  if (n == 0 || m == 0) {
    // Every existing point goes to the other side's dustbin with probability 1.
    Eigen::MatrixXd log_p = Eigen::MatrixXd::Constant(n + 1, m + 1, kNegInf);
    if (n == 0) log_p.row(0).head(m).setZero();
    if (m == 0) log_p.col(0).head(n).setZero();
    return log_p;
  }

  // Eq. 4: S' with the dustbin row and column, all in logit units.
  Eigen::MatrixXd z = Eigen::MatrixXd::Constant(n + 1, m + 1, config.dustbin_score);
  z.topLeftCorner(n, m) = scores / config.temperature;

  // Marginals: unit mass per real point, m for the source dustbin row, n for the target dustbin
  // column (SuperGlue). Both total n + m.
  Eigen::VectorXd log_a = Eigen::VectorXd::Zero(n + 1);
  Eigen::VectorXd log_b = Eigen::VectorXd::Zero(m + 1);
  log_a(n) = std::log(static_cast<double>(m));
  log_b(m) = std::log(static_cast<double>(n));

  Eigen::VectorXd u = Eigen::VectorXd::Zero(n + 1);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(m + 1);
  // Same iteration in two numerical forms. When every exp(z - max z) stays far inside double
  // range (range < 600 logits, e^-600 ~ 1e-261), the scaling form u' = a / (K v'),
  // v' = b / (K^T u') with K = exp(z - max z) needs one exp per entry in total instead of two per
  // iteration, and is ~50x faster on whole images (2800 x 2200 keypoints: ~0.2 s instead of
  // ~10 s). Otherwise (extreme scores) the log-domain form keeps everything finite.
  const double z_max = z.maxCoeff();
  if (config.iterations > 0 && z_max - z.minCoeff() < 600.0) {
    const Eigen::MatrixXd K = (z.array() - z_max).exp().matrix();
    const Eigen::VectorXd a = log_a.array().exp().matrix(), b = log_b.array().exp().matrix();
    Eigen::VectorXd u_scale = Eigen::VectorXd::Ones(n + 1), v_scale = Eigen::VectorXd::Ones(m + 1);
    for (int it = 0; it < config.iterations; ++it) {
      u_scale = a.array() / (K * v_scale).array();
      v_scale = b.array() / (K.transpose() * u_scale).array();
    }
    // exp(u) exp(v) exp(z) = u' v' K, with the shift z_max carried by u.
    u = u_scale.array().log() - z_max;
    v = v_scale.array().log();
  } else {
    for (int it = 0; it < config.iterations; ++it) {
      u = log_a - RowLogSumExp(z.rowwise() + v.transpose());
      v = log_b - RowLogSumExp((z.colwise() + u).transpose());
    }
  }
  Eigen::MatrixXd log_p = z;
  log_p.colwise() += u;
  log_p.rowwise() += v.transpose();
  return log_p;
}

std::vector<SinkhornMatch> ExtractSinkhornMatches(const Eigen::MatrixXd& log_assignment,
                                                  const SinkhornConfig& config) {
  std::vector<SinkhornMatch> matches;
  const Eigen::Index n = log_assignment.rows() - 1;
  const Eigen::Index m = log_assignment.cols() - 1;
  if (n <= 0 || m <= 0) return matches;
  const auto real = log_assignment.topLeftCorner(n, m);
  // Best source of every target (first on ties), dustbin row excluded.
  std::vector<Eigen::Index> best_source(static_cast<std::size_t>(m));
  for (Eigen::Index k = 0; k < m; ++k) real.col(k).maxCoeff(&best_source[k]);
  const double log_min = std::log(config.min_probability);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Index k = 0;
    const double best = real.row(i).maxCoeff(&k);
    if (!(best >= log_min)) continue;
    if (config.mutual && best_source[static_cast<std::size_t>(k)] != i) continue;
    matches.push_back({static_cast<int>(i), static_cast<int>(k), std::exp(best)});
  }
  return matches;
}

std::vector<SinkhornMatch> MatchSinkhorn(const Eigen::MatrixXd& descriptors_source,
                                         const Eigen::MatrixXd& descriptors_target,
                                         const SinkhornConfig& config,
                                         Eigen::MatrixXd* log_assignment) {
  const Eigen::Index n = descriptors_source.rows();
  const Eigen::Index m = descriptors_target.rows();
  if (n > 0 && m > 0 && descriptors_source.cols() != descriptors_target.cols()) {
    throw MakeInputError("descriptors_target", "have dimension " +
                                                   std::to_string(descriptors_target.cols()) +
                                                   ", expected the source's " +
                                                   std::to_string(descriptors_source.cols()));
  }
  if (!descriptors_source.allFinite()) {
    throw MakeInputError("descriptors_source", "contain NaN or infinity");
  }
  if (!descriptors_target.allFinite()) {
    throw MakeInputError("descriptors_target", "contain NaN or infinity");
  }
  Eigen::MatrixXd scores(n, m);  // Eq. 3
  if (n > 0 && m > 0) scores.noalias() = descriptors_source * descriptors_target.transpose();
  Eigen::MatrixXd log_p = SinkhornLogAssignment(scores, config);
  std::vector<SinkhornMatch> matches = ExtractSinkhornMatches(log_p, config);
  if (log_assignment != nullptr) *log_assignment = std::move(log_p);
  return matches;
}

std::vector<SinkhornMatch> MatchSinkhorn(const Eigen::MatrixXf& descriptors_source,
                                         const Eigen::MatrixXf& descriptors_target,
                                         const SinkhornConfig& config,
                                         Eigen::MatrixXd* log_assignment, int threads) {
  const Eigen::Index n = descriptors_source.rows();
  const Eigen::Index m = descriptors_target.rows();
  const bool inputs_usable = n > 0 && m > 0 &&
                             descriptors_source.cols() == descriptors_target.cols() &&
                             descriptors_source.allFinite() && descriptors_target.allFinite();
  if (log_assignment == nullptr && inputs_usable && config.iterations > 0 &&
      config.temperature > 0.0 && std::isfinite(config.temperature) &&
      std::isfinite(config.dustbin_score)) {
    std::vector<SinkhornMatch> matches;
    if (SinglePrecisionSinkhorn(descriptors_source, descriptors_target, config, threads,
                                &matches)) {
      return matches;
    }
  }
  // Everything else (log P wanted, empty or invalid input, extreme scores) in double.
  return MatchSinkhorn(Eigen::MatrixXd(descriptors_source.cast<double>()),
                       Eigen::MatrixXd(descriptors_target.cast<double>()), config, log_assignment);
}

}  // namespace zeroreg
