#include "recordings/place_recognition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

#include "zeroreg/error.hpp"

namespace zeroreg {

namespace {

// Uniform in [0, 1) from the engine's raw bits: std::uniform_real_distribution is not the same on
// every standard library, the engine is.
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Squared distances of every row of `x` to every row of `centers` (rows x centers), up to the
// rows' own norm, which does not change the nearest centre: |c|^2 - 2 x.c.
Eigen::MatrixXf PartialDistances(const Eigen::MatrixXf& x, const Eigen::MatrixXf& centers,
                                 const Eigen::VectorXf& center_norms) {
  Eigen::MatrixXf d = -2.0f * (x * centers.transpose());
  d.rowwise() += center_norms.transpose();
  return d;
}

std::vector<int> Nearest(const Eigen::MatrixXf& x, const Eigen::MatrixXf& centers,
                         const Eigen::VectorXf& center_norms) {
  std::vector<int> out(static_cast<std::size_t>(x.rows()), 0);
  constexpr Eigen::Index kBlock = 4096;  // bounds the distance matrix's memory
  for (Eigen::Index start = 0; start < x.rows(); start += kBlock) {
    const Eigen::Index n = std::min(kBlock, x.rows() - start);
    const Eigen::MatrixXf d = PartialDistances(x.middleRows(start, n), centers, center_norms);
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      for (Eigen::Index j = 1; j < d.cols(); ++j) {
        if (d(i, j) < d(i, best)) best = j;
      }
      out[static_cast<std::size_t>(start + i)] = static_cast<int>(best);
    }
  }
  return out;
}

}  // namespace

void ValidateVocabularyConfig(const VocabularyConfig& c) {
  const auto require = [](bool ok, const std::string& field, int value) {
    if (!ok) {
      throw InputError("vocabulary." + field + " = " + std::to_string(value) + ": expected >= 1");
    }
  };
  require(c.words >= 1, "words", c.words);
  if (c.iterations < 0) {
    throw InputError("vocabulary.iterations = " + std::to_string(c.iterations) + ": expected >= 0");
  }
  require(c.max_descriptors >= 1, "max_descriptors", c.max_descriptors);
}

Vocabulary::Vocabulary(Eigen::MatrixXf centers) : centers_(std::move(centers)) {
  if (centers_.rows() < 1 || centers_.cols() < 1) {
    throw InputError("Vocabulary: " + std::to_string(centers_.rows()) + "x" +
                     std::to_string(centers_.cols()) + " centres: expected at least one word");
  }
  center_norms_ = centers_.rowwise().squaredNorm();
}

Vocabulary Vocabulary::Train(const std::vector<Eigen::MatrixXf>& descriptor_sets,
                             const VocabularyConfig& config) {
  ValidateVocabularyConfig(config);
  Eigen::Index total = 0, dim = -1;
  for (const Eigen::MatrixXf& set : descriptor_sets) {
    if (set.rows() == 0) continue;
    if (dim >= 0 && set.cols() != dim) {
      throw InputError("Vocabulary::Train: descriptors of " + std::to_string(set.cols()) + " and " +
                       std::to_string(dim) + " dimensions: expected one dimension");
    }
    dim = set.cols();
    total += set.rows();
  }
  if (total == 0) throw InputError("Vocabulary::Train: no descriptors to build words from");

  // The sample: every descriptor, or an even stride through all of them.
  const Eigen::Index n = std::min<Eigen::Index>(total, config.max_descriptors);
  Eigen::MatrixXf x(n, dim);
  {
    Eigen::Index seen = 0, taken = 0;
    for (const Eigen::MatrixXf& set : descriptor_sets) {
      for (Eigen::Index r = 0; r < set.rows(); ++r, ++seen) {
        // Row `seen` is taken when it is the first at or after taken * total / n.
        if (taken < n && seen * n >= taken * total) x.row(taken++) = set.row(r);
      }
    }
  }

  // k-means++ seeding (Arthur and Vassilvitskii 2007): each next centre drawn with probability
  // proportional to the squared distance to the nearest centre so far.
  std::mt19937_64 rng(config.seed);
  const Eigen::Index k = std::min<Eigen::Index>(config.words, n);
  Eigen::MatrixXf centers(k, dim);
  centers.row(0) = x.row(static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(n)));
  Eigen::VectorXd nearest = (x.rowwise() - centers.row(0)).rowwise().squaredNorm().cast<double>();
  Eigen::Index made = 1;
  for (; made < k; ++made) {
    const double sum = nearest.sum();
    if (!(sum > 0.0)) break;  // fewer distinct descriptors than words
    const double target = Uniform(rng) * sum;
    double acc = 0.0;
    Eigen::Index pick = n - 1;
    for (Eigen::Index i = 0; i < n; ++i) {
      acc += nearest(i);
      if (acc > target && nearest(i) > 0.0) {
        pick = i;
        break;
      }
    }
    while (nearest(pick) <= 0.0 && pick > 0) --pick;  // rounding at the end of the sum
    centers.row(made) = x.row(pick);
    nearest =
        nearest.cwiseMin((x.rowwise() - centers.row(made)).rowwise().squaredNorm().cast<double>());
  }
  centers.conservativeResize(made, Eigen::NoChange);

  // Lloyd iterations; an emptied word keeps its centre.
  for (int it = 0; it < config.iterations; ++it) {
    const Eigen::VectorXf norms = centers.rowwise().squaredNorm();
    const std::vector<int> assign = Nearest(x, centers, norms);
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(centers.rows(), dim);
    std::vector<int> counts(static_cast<std::size_t>(centers.rows()), 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      sums.row(assign[static_cast<std::size_t>(i)]) += x.row(i).cast<double>();
      ++counts[static_cast<std::size_t>(assign[static_cast<std::size_t>(i)])];
    }
    Eigen::MatrixXf next = centers;
    for (Eigen::Index j = 0; j < centers.rows(); ++j) {
      if (counts[static_cast<std::size_t>(j)] > 0) {
        next.row(j) = (sums.row(j) / counts[static_cast<std::size_t>(j)]).cast<float>();
      }
    }
    const bool stable = next == centers;
    centers = std::move(next);
    if (stable) break;
  }
  return Vocabulary(std::move(centers));
}

std::vector<int> Vocabulary::Quantize(const Eigen::MatrixXf& descriptors) const {
  if (descriptors.rows() > 0 && descriptors.cols() != centers_.cols()) {
    throw InputError("Vocabulary::Quantize: descriptors of " + std::to_string(descriptors.cols()) +
                     " dimensions: expected " + std::to_string(centers_.cols()));
  }
  if (descriptors.rows() == 0) return {};
  return Nearest(descriptors, centers_, center_norms_);
}

PlaceIndex::PlaceIndex(Vocabulary vocabulary) : vocabulary_(std::move(vocabulary)) {
  if (vocabulary_.size() < 1) throw InputError("PlaceIndex: the vocabulary has no words");
}

int PlaceIndex::Add(const Eigen::MatrixXf& descriptors) {
  if (final_) throw std::logic_error("PlaceIndex::Add after Finalize");
  std::vector<int> words = vocabulary_.Quantize(descriptors);
  std::sort(words.begin(), words.end());
  std::vector<std::pair<int, int>> counts;
  for (int w : words) {
    if (!counts.empty() && counts.back().first == w) {
      ++counts.back().second;
    } else {
      counts.emplace_back(w, 1);
    }
  }
  counts_.push_back(std::move(counts));
  return size() - 1;
}

void PlaceIndex::Finalize() {
  std::vector<int> holders(static_cast<std::size_t>(vocabulary_.size()), 0);
  for (const auto& counts : counts_) {
    for (const auto& [word, count] : counts) ++holders[static_cast<std::size_t>(word)];
  }
  const double n = static_cast<double>(counts_.size());
  idf_.assign(holders.size(), 0.0);
  for (std::size_t w = 0; w < holders.size(); ++w) {
    if (holders[w] > 0) idf_[w] = std::log(n / holders[w]);
  }
  weights_.clear();
  for (const auto& counts : counts_) {
    double total = 0.0;
    for (const auto& wc : counts) total += wc.second;
    std::vector<std::pair<int, float>> weights;
    double norm2 = 0.0;
    for (const auto& [word, count] : counts) {
      const double weight = count / total * idf_[static_cast<std::size_t>(word)];
      if (weight > 0.0) {
        weights.emplace_back(word, static_cast<float>(weight));
        norm2 += weight * weight;
      }
    }
    const double norm = std::sqrt(norm2);
    for (auto& wv : weights) wv.second = static_cast<float>(wv.second / norm);
    weights_.push_back(std::move(weights));
  }
  final_ = true;
}

void PlaceIndex::RequireFinal(const char* what) const {
  if (!final_) throw std::logic_error(std::string("PlaceIndex::") + what + " before Finalize");
}

double PlaceIndex::Idf(int word) const {
  RequireFinal("Idf");
  if (word < 0 || word >= vocabulary_.size()) {
    throw InputError("PlaceIndex::Idf: word " + std::to_string(word) + ": expected 0.." +
                     std::to_string(vocabulary_.size() - 1));
  }
  return idf_[static_cast<std::size_t>(word)];
}

double PlaceIndex::Similarity(int a, int b) const {
  RequireFinal("Similarity");
  if (a < 0 || b < 0 || a >= size() || b >= size()) {
    throw InputError("PlaceIndex::Similarity: keyframes " + std::to_string(a) + ", " +
                     std::to_string(b) + ": expected ids 0.." + std::to_string(size() - 1));
  }
  const auto& x = weights_[static_cast<std::size_t>(a)];
  const auto& y = weights_[static_cast<std::size_t>(b)];
  double dot = 0.0;
  std::size_t i = 0, j = 0;
  while (i < x.size() && j < y.size()) {
    if (x[i].first < y[j].first) {
      ++i;
    } else if (y[j].first < x[i].first) {
      ++j;
    } else {
      dot += static_cast<double>(x[i++].second) * y[j++].second;
    }
  }
  return dot;
}

std::vector<PlaceCandidate> PlaceIndex::Rank(int query, const std::vector<int>& database,
                                             int k) const {
  RequireFinal("Rank");
  std::vector<PlaceCandidate> all;
  for (int id : database) {
    if (id != query) all.push_back({id, Similarity(query, id)});
  }
  std::sort(all.begin(), all.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.score != b.score ? a.score > b.score : a.id < b.id;
  });
  if (k >= 0 && static_cast<std::size_t>(k) < all.size()) all.resize(static_cast<std::size_t>(k));
  return all;
}

int MutualMatches(const Eigen::MatrixXf& a, const Eigen::MatrixXf& b, float min_cosine,
                  int max_rows) {
  if (a.rows() > 0 && b.rows() > 0 && a.cols() != b.cols()) {
    throw InputError("MutualMatches: descriptors of " + std::to_string(a.cols()) + " and " +
                     std::to_string(b.cols()) + " dimensions: expected one dimension");
  }
  const Eigen::Index na = std::min<Eigen::Index>(a.rows(), max_rows);
  const Eigen::Index nb = std::min<Eigen::Index>(b.rows(), max_rows);
  if (na == 0 || nb == 0) return 0;
  const Eigen::MatrixXf s = a.topRows(na) * b.topRows(nb).transpose();
  // Best column of each row and best row of each column; ties go to the lower index.
  std::vector<Eigen::Index> row_best(static_cast<std::size_t>(na), 0);
  std::vector<Eigen::Index> col_best(static_cast<std::size_t>(nb), 0);
  for (Eigen::Index i = 0; i < na; ++i) {
    for (Eigen::Index j = 0; j < nb; ++j) {
      if (s(i, j) > s(i, row_best[static_cast<std::size_t>(i)])) {
        row_best[static_cast<std::size_t>(i)] = j;
      }
      if (s(i, j) > s(col_best[static_cast<std::size_t>(j)], j)) {
        col_best[static_cast<std::size_t>(j)] = i;
      }
    }
  }
  int matches = 0;
  for (Eigen::Index i = 0; i < na; ++i) {
    const Eigen::Index j = row_best[static_cast<std::size_t>(i)];
    if (col_best[static_cast<std::size_t>(j)] == i && s(i, j) >= min_cosine) ++matches;
  }
  return matches;
}

std::vector<PlaceCandidate> RerankByMatches(const std::vector<PlaceCandidate>& candidates,
                                            int query,
                                            const std::vector<Eigen::MatrixXf>& descriptors,
                                            float min_cosine, int max_rows) {
  const auto at = [&](int id) -> const Eigen::MatrixXf& {
    if (id < 0 || static_cast<std::size_t>(id) >= descriptors.size()) {
      throw InputError("RerankByMatches: keyframe " + std::to_string(id) + ": expected ids 0.." +
                       std::to_string(static_cast<long long>(descriptors.size()) - 1));
    }
    return descriptors[static_cast<std::size_t>(id)];
  };
  std::vector<PlaceCandidate> out;
  for (const PlaceCandidate& c : candidates) {
    out.push_back(
        {c.id, static_cast<double>(MutualMatches(at(query), at(c.id), min_cosine, max_rows))});
  }
  std::stable_sort(out.begin(), out.end(), [](const PlaceCandidate& x, const PlaceCandidate& y) {
    return x.score > y.score;
  });
  return out;
}

std::vector<std::pair<int, int>> FarApartCandidates(const PlaceIndex& index, int min_separation,
                                                    int k) {
  std::vector<std::pair<int, int>> pairs;
  for (int q = 0; q < index.size(); ++q) {
    std::vector<int> far;
    for (int id = 0; id < index.size(); ++id) {
      if (std::abs(id - q) >= min_separation) far.push_back(id);
    }
    for (const PlaceCandidate& c : index.Rank(q, far, k)) {
      if (c.score <= 0.0) break;  // shares no weighted word: nothing suggests the same place
      const std::pair<int, int> pair(std::min(q, c.id), std::max(q, c.id));
      if (std::find(pairs.begin(), pairs.end(), pair) == pairs.end()) pairs.push_back(pair);
    }
  }
  return pairs;
}

std::vector<Eigen::MatrixXf> WithNeighbours(const std::vector<Eigen::MatrixXf>& sets,
                                            const std::vector<int>& recording_sizes,
                                            int neighbours) {
  int total = 0;
  for (int n : recording_sizes) total += n;
  if (total != static_cast<int>(sets.size()) || neighbours < 0) {
    throw InputError("WithNeighbours: recordings of " + std::to_string(total) + " keyframes for " +
                     std::to_string(sets.size()) + " descriptor sets, neighbours " +
                     std::to_string(neighbours) + "; expected equal counts and neighbours >= 0");
  }
  if (neighbours == 0) return sets;
  std::vector<Eigen::MatrixXf> out;
  out.reserve(sets.size());
  int first = 0;
  for (int n : recording_sizes) {
    for (int i = 0; i < n; ++i) {
      const int lo = std::max(0, i - neighbours), hi = std::min(n - 1, i + neighbours);
      Eigen::Index rows = 0, cols = 0;
      for (int j = lo; j <= hi; ++j) {
        rows += sets[static_cast<std::size_t>(first + j)].rows();
        cols = std::max(cols, sets[static_cast<std::size_t>(first + j)].cols());
      }
      Eigen::MatrixXf d(rows, cols);
      Eigen::Index row = 0;
      for (int j = lo; j <= hi; ++j) {
        const Eigen::MatrixXf& part = sets[static_cast<std::size_t>(first + j)];
        if (part.rows() == 0) continue;
        d.middleRows(row, part.rows()) = part;
        row += part.rows();
      }
      out.push_back(std::move(d));
    }
    first += n;
  }
  return out;
}

}  // namespace zeroreg
