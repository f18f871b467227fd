// Synthetic object layouts with a known correspondence, for the object-matching tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace zeroreg::testing {

// Bit-exact on every standard library (the std distributions are not).
inline double Uniform(std::mt19937_64& rng, double lo = 0.0, double hi = 1.0) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}
inline double Gaussian(std::mt19937_64& rng) {
  const double u1 = std::max(Uniform(rng), 1e-300);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * Uniform(rng));
}

// Class embeddings that, like CLIP text embeddings, share a common component (cos ~ 0.5 between
// different classes).
inline Eigen::MatrixXd ClassEmbeddings(int classes, int dim, std::mt19937_64& rng) {
  Eigen::VectorXd common(dim);
  for (int i = 0; i < dim; ++i) common(i) = Gaussian(rng);
  Eigen::MatrixXd e(classes, dim);
  for (int c = 0; c < classes; ++c) {
    for (int i = 0; i < dim; ++i) e(c, i) = common(i) + Gaussian(rng);
  }
  return e;
}

struct ScenePair {
  Eigen::MatrixXd centroids_p, centroids_q;  // n x 3, m x 3
  Eigen::MatrixXd semantics_p, semantics_q;  // n x d, m x d
  std::vector<std::string> labels_p, labels_q;
  std::vector<int> truth;  // source -> target, -1 when the object is not in the target
};

// How the target's part of the source is chosen.
enum class Overlap {
  kCrop,    // like two scans: the target sees the part of the source with the largest x, and the
            // extras lie beyond it (x > side: new area seen only by the target)
  kRandom,  // a random subset, extras anywhere in the room (harder: every neighbourhood changes)
};

// n source objects at least min_spacing apart in a room whose area grows with n; the target keeps
// keep_fraction of them, adds `extras` new objects, is rigidly moved (rotation about z,
// translation), gets Gaussian centroid noise (sigma per axis, metres) and is shuffled.
inline ScenePair MakeScenePair(int n, double keep_fraction, int extras, double noise, int classes,
                               std::uint64_t seed, Overlap overlap = Overlap::kCrop,
                               double min_spacing = 0.6) {
  std::mt19937_64 rng(seed);
  const Eigen::MatrixXd embeddings = ClassEmbeddings(classes, 16, rng);
  const double side = 1.6 * std::sqrt(static_cast<double>(n));
  std::vector<Eigen::Vector3d> positions;
  auto place = [&](double x_lo, double x_hi) {
    for (;;) {
      const Eigen::Vector3d p(Uniform(rng, x_lo, x_hi), Uniform(rng, 0, side), Uniform(rng, 0, 2));
      bool ok = true;
      for (const auto& q : positions) ok = ok && (p - q).norm() >= min_spacing;
      if (ok) return p;
    }
  };
  ScenePair s;
  std::vector<int> cls;
  for (int j = 0; j < n; ++j) {
    positions.push_back(place(0, side));
    cls.push_back(static_cast<int>(rng() % static_cast<std::uint64_t>(classes)));
  }
  // Extras: beyond the room (kCrop, in a strip as deep as the density needs) or inside it.
  const double strip = side * extras / std::max(n, 1);
  for (int e = 0; e < extras; ++e) {
    positions.push_back(overlap == Overlap::kCrop ? place(side, side + strip) : place(0, side));
    cls.push_back(static_cast<int>(rng() % static_cast<std::uint64_t>(classes)));
  }
  s.centroids_p.resize(n, 3);
  s.semantics_p.resize(n, embeddings.cols());
  for (int j = 0; j < n; ++j) {
    s.centroids_p.row(j) = positions[j].transpose();
    s.semantics_p.row(j) = embeddings.row(cls[j]);
    s.labels_p.push_back("class" + std::to_string(cls[j]));
  }
  // Which source objects the target keeps, plus the extras (indices >= n).
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  if (overlap == Overlap::kCrop) {
    // Keep the objects with the largest x: the part of the room next to the new area (x > side).
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return positions[a].x() > positions[b].x(); });
  }
  std::vector<int> members(order.begin(),
                           order.begin() + static_cast<int>(std::lround(keep_fraction * n)));
  for (int e = 0; e < extras; ++e) members.push_back(n + e);
  std::shuffle(members.begin(), members.end(), rng);

  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(Uniform(rng, -M_PI, M_PI), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d translation(Uniform(rng, -3, 3), Uniform(rng, -3, 3), Uniform(rng, -1, 1));
  const int m = static_cast<int>(members.size());
  s.centroids_q.resize(m, 3);
  s.semantics_q.resize(m, embeddings.cols());
  s.truth.assign(n, -1);
  for (int k = 0; k < m; ++k) {
    const int src = members[k];
    const Eigen::Vector3d noisy(noise * Gaussian(rng), noise * Gaussian(rng),
                                noise * Gaussian(rng));
    s.centroids_q.row(k) = (rotation * positions[src] + translation + noisy).transpose();
    s.semantics_q.row(k) = embeddings.row(cls[src]);
    s.labels_q.push_back("class" + std::to_string(cls[src]));
    if (src < n) s.truth[src] = k;
  }
  return s;
}

}  // namespace zeroreg::testing
