#include "estimate/max_clique.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

// Vertex sets as bitsets over the (renumbered) vertices: the branch and bound intersects a
// candidate set with a neighbourhood at every node, a word-parallel AND here (San Segundo et al.,
// "An exact bit-parallel algorithm for the maximum clique problem", 2011, BBMC).
using Bits = std::vector<std::uint64_t>;

void Set(Bits& b, int i) { b[static_cast<size_t>(i) >> 6] |= std::uint64_t{1} << (i & 63); }
void Reset(Bits& b, int i) { b[static_cast<size_t>(i) >> 6] &= ~(std::uint64_t{1} << (i & 63)); }
bool Empty(const Bits& b) {
  return std::all_of(b.begin(), b.end(), [](std::uint64_t w) { return w == 0; });
}
int Count(const Bits& b) {
  int c = 0;
  for (std::uint64_t w : b) c += __builtin_popcountll(w);
  return c;
}
int First(const Bits& b) {  // lowest set bit, -1 when empty
  for (size_t k = 0; k < b.size(); ++k) {
    if (b[k] != 0) return static_cast<int>(k * 64 + static_cast<size_t>(__builtin_ctzll(b[k])));
  }
  return -1;
}

// Core number of every vertex (the largest k such that the vertex is in the k-core), by repeatedly
// removing a vertex of least remaining degree (Batagelj & Zaversnik 2003). A vertex of core number
// c lies in no clique of more than c + 1 vertices, which prunes most of a sparse consistency graph
// before the exact search (the k-core pruning of KISS-Matcher and of PMC).
std::vector<int> CoreNumbers(const std::vector<std::vector<int>>& adjacency) {
  const int n = static_cast<int>(adjacency.size());
  std::vector<int> degree(n), core(n, 0);
  int max_degree = 0;
  for (int v = 0; v < n; ++v) {
    degree[v] = static_cast<int>(adjacency[v].size());
    max_degree = std::max(max_degree, degree[v]);
  }
  std::vector<std::vector<int>> buckets(static_cast<size_t>(max_degree) + 1);
  for (int v = 0; v < n; ++v) buckets[degree[v]].push_back(v);
  std::vector<bool> removed(n, false);
  int current = 0;
  for (int done = 0, d = 0; done < n;) {
    // Buckets hold stale entries (a vertex moves down when a neighbour goes); skip them.
    while (d > 0 && !buckets[d - 1].empty()) --d;
    if (buckets[d].empty()) {
      ++d;
      continue;
    }
    const int v = buckets[d].back();
    buckets[d].pop_back();
    if (removed[v] || degree[v] != d) continue;
    removed[v] = true;
    current = std::max(current, d);
    core[v] = current;
    ++done;
    for (int u : adjacency[v]) {
      if (removed[u]) continue;
      --degree[u];
      buckets[degree[u]].push_back(u);
    }
  }
  return core;
}

class CliqueSearch {
 public:
  CliqueSearch(const std::vector<Bits>& neighbours, long long budget)
      : neighbours_(neighbours), budget_(budget) {}

  // Branch and bound of Tomita & Seki (MCQ, 2003) on bitsets: colour the candidates greedily
  // (vertices of one colour are pairwise non-adjacent, so a clique takes at most one per colour)
  // and expand them from the highest colour down, stopping where |R| + colour cannot beat the best.
  void Expand(std::vector<int>& clique, Bits candidates) {
    if (++nodes_ > budget_) {
      exhausted_ = true;
      return;
    }
    std::vector<int> order, colour;
    order.reserve(static_cast<size_t>(Count(candidates)));
    colour.reserve(order.capacity());
    Bits uncoloured = candidates;
    for (int k = 1; !Empty(uncoloured); ++k) {
      Bits free = uncoloured;
      for (int v = First(free); v >= 0; v = First(free)) {
        Reset(free, v);
        Reset(uncoloured, v);
        for (size_t w = 0; w < free.size(); ++w) free[w] &= ~neighbours_[v][w];
        order.push_back(v);
        colour.push_back(k);
      }
    }
    for (int i = static_cast<int>(order.size()) - 1; i >= 0; --i) {
      if (static_cast<int>(clique.size()) + colour[i] <= static_cast<int>(best_.size())) return;
      const int v = order[i];
      clique.push_back(v);
      Bits next = candidates;
      for (size_t w = 0; w < next.size(); ++w) next[w] &= neighbours_[v][w];
      if (Empty(next)) {
        if (clique.size() > best_.size()) best_ = clique;
      } else {
        Expand(clique, std::move(next));
      }
      clique.pop_back();
      Reset(candidates, v);
      if (exhausted_) return;
    }
  }

  std::vector<int> best_;
  long long nodes_ = 0;
  bool exhausted_ = false;

 private:
  const std::vector<Bits>& neighbours_;
  long long budget_;
};

}  // namespace

CliqueSearchResult MaximumClique(const std::vector<std::vector<int>>& adjacency,
                                 long long max_search_nodes) {
  CliqueSearchResult result;
  const int n = static_cast<int>(adjacency.size());
  if (n == 0) return result;
  const std::vector<int> core = CoreNumbers(adjacency);
  // Renumber: densest core first (ties: higher degree, then lower index), so that the greedy start
  // and the bit order of the search meet the large cliques early.
  std::vector<int> by_rank(n);
  std::iota(by_rank.begin(), by_rank.end(), 0);
  std::sort(by_rank.begin(), by_rank.end(), [&](int a, int b) {
    if (core[a] != core[b]) return core[a] > core[b];
    if (adjacency[a].size() != adjacency[b].size()) {
      return adjacency[a].size() > adjacency[b].size();
    }
    return a < b;
  });
  std::vector<int> rank(n);
  for (int k = 0; k < n; ++k) rank[by_rank[k]] = k;
  const size_t words = (static_cast<size_t>(n) + 63) / 64;
  std::vector<Bits> neighbours(n, Bits(words, 0));
  for (int v = 0; v < n; ++v) {
    for (int u : adjacency[v]) Set(neighbours[rank[v]], rank[u]);
  }

  // Greedy lower bound: from each of the densest vertices, repeatedly add the first (densest)
  // candidate adjacent to everything chosen so far.
  CliqueSearch search(neighbours, max_search_nodes);
  search.best_ = {0};
  const int starts = std::min(n, 64);
  for (int v = 0; v < starts; ++v) {
    std::vector<int> clique = {v};
    Bits candidates = neighbours[v];
    for (int u = First(candidates); u >= 0; u = First(candidates)) {
      clique.push_back(u);
      for (size_t w = 0; w < words; ++w) candidates[w] &= neighbours[u][w];
    }
    if (clique.size() > search.best_.size()) search.best_ = clique;
  }

  // Exact search over the vertices whose core number still allows a larger clique.
  Bits candidates(words, 0);
  for (int k = 0; k < n; ++k) {
    if (core[by_rank[k]] + 1 > static_cast<int>(search.best_.size())) Set(candidates, k);
  }
  if (!Empty(candidates)) {
    std::vector<int> clique;
    search.Expand(clique, candidates);
  }
  result.exact = !search.exhausted_;
  result.search_nodes = search.nodes_;
  for (int k : search.best_) result.clique.push_back(by_rank[k]);
  std::sort(result.clique.begin(), result.clique.end());
  return result;
}

RansacResult EstimateRigidClique(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target,
                                 const std::vector<float>& scores, const RansacConfig& config) {
  RansacResult result;
  const int n = static_cast<int>(source.size());
  result.is_inlier.assign(source.size(), false);
  if (n < 3) return result;

  // The graph is quadratic in the correspondences: keep the most confident ones.
  std::vector<int> kept(n);
  std::iota(kept.begin(), kept.end(), 0);
  const int cap = config.clique_max_correspondences;
  if (n > cap) {
    if (scores.size() == source.size()) {
      std::stable_sort(kept.begin(), kept.end(),
                       [&](int a, int b) { return scores[a] > scores[b]; });
    }
    kept.resize(static_cast<size_t>(cap));
    std::sort(kept.begin(), kept.end());
  }
  const int m = static_cast<int>(kept.size());

  // Two inliers are each within the noise bound of their true positions, so their source and
  // target lengths differ by at most twice the bound (the pairwise invariant of TEASER++).
  const double noise =
      config.clique_noise_bound_m > 0 ? config.clique_noise_bound_m : config.inlier_threshold_m;
  std::vector<std::vector<int>> adjacency(static_cast<size_t>(m));
  for (int a = 0; a < m; ++a) {
    const Eigen::Vector3d& sa = source[kept[a]];
    const Eigen::Vector3d& ta = target[kept[a]];
    for (int b = a + 1; b < m; ++b) {
      const double ds = (sa - source[kept[b]]).norm();
      const double dt = (ta - target[kept[b]]).norm();
      if (std::abs(ds - dt) <= 2 * noise) {
        adjacency[a].push_back(b);
        adjacency[b].push_back(a);
      }
    }
  }
  const CliqueSearchResult clique = MaximumClique(adjacency, config.clique_max_search_nodes);
  result.iterations = static_cast<int>(std::min<long long>(clique.search_nodes, 2147483647));
  if (clique.clique.size() < 3) return result;
  std::vector<int> members;
  for (int k : clique.clique) members.push_back(kept[k]);
  if (!FitRigidTransform(source, target, members, &result.T_target_source)) return result;
  result.found = true;

  // The clique's members agree pairwise within 2 x the bound, not necessarily with one transform
  // within the bound: the inliers of the fit, over all correspondences, decide, refitted until
  // stable (the same final step as EstimateRigidRansac).
  RefitOnInliers(source, target, config.inlier_threshold_m, &result);
  return result;
}

void CheckEstimatorName(const RansacConfig& config) {
  if (config.estimator != "ransac" && config.estimator != "clique") {
    throw MakeInputError(
        "ransac.estimator",
        "'" + config.estimator + "' is not an estimator; expected ransac or clique");
  }
}

RansacResult EstimateRigid(const std::vector<Eigen::Vector3d>& source,
                           const std::vector<Eigen::Vector3d>& target,
                           const std::vector<float>& scores, const RansacConfig& config,
                           std::uint64_t seed) {
  CheckEstimatorName(config);
  if (config.estimator == "clique") return EstimateRigidClique(source, target, scores, config);
  return EstimateRigidRansac(source, target, config, seed);
}

}  // namespace zeroreg
