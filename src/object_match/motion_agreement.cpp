#include "object_match/motion_agreement.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <tuple>

#include "estimate/max_clique.hpp"
#include "estimate/rigid_ransac.hpp"

namespace zeroreg {
namespace {

// Share of `m`'s inliers that motion T carries to within threshold_m of their partners.
double ShareCarried(const Transform& T, const MatchMotion& m, double threshold_m) {
  if (m.source.empty()) return 0.0;
  return static_cast<double>(CountCarried(T, m, threshold_m)) /
         static_cast<double>(m.source.size());
}

}  // namespace

bool MotionsAgree(const MatchMotion& a, const MatchMotion& b, double threshold_m) {
  // A match without inliers has no motion of its own (fewer than three point matches).
  if (a.source.empty() || b.source.empty()) return false;
  // One motion fitted to both matches' inliers: two objects far apart fix it far better than
  // either alone (a lever arm of metres instead of centimetres), and if the two move together it
  // explains both.
  std::vector<Eigen::Vector3d> source = a.source, target = a.target;
  source.insert(source.end(), b.source.begin(), b.source.end());
  target.insert(target.end(), b.target.begin(), b.target.end());
  std::vector<int> all(source.size());
  std::iota(all.begin(), all.end(), 0);
  Transform joint;
  if (!FitRigidTransform(source, target, all, &joint)) return false;
  return ShareCarried(joint, a, threshold_m) >= 0.5 && ShareCarried(joint, b, threshold_m) >= 0.5;
}

int CountCarried(const Transform& T, const MatchMotion& points, double threshold_m) {
  int carried = 0;
  for (size_t i = 0; i < points.source.size(); ++i) {
    const Eigen::Vector3d moved = (T * points.source[i].homogeneous()).head<3>();
    if ((moved - points.target[i]).norm() <= threshold_m) ++carried;
  }
  return carried;
}

std::vector<int> MatchesThatMoveTogether(const std::vector<MatchMotion>& motions,
                                         double threshold_m) {
  std::vector<int> consensus = MatchesInConsensus(motions, threshold_m);
  if (!consensus.empty()) return consensus;
  std::vector<int> all(motions.size());
  std::iota(all.begin(), all.end(), 0);
  return all;
}

std::vector<int> MatchesInConsensus(const std::vector<MatchMotion>& motions, double threshold_m) {
  const int n = static_cast<int>(motions.size());
  if (n < 2) return {};
  std::vector<std::vector<int>> agree(n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (MotionsAgree(motions[i], motions[j], threshold_m)) {
        agree[i].push_back(j);
        agree[j].push_back(i);
      }
    }
  }
  // A handful of matches: the exact search finishes in a few nodes.
  const CliqueSearchResult largest = MaximumClique(agree, 1000000);
  // No strict majority (a clique of one is no agreement): nothing is decided.
  if (largest.clique.size() < 2 || 2 * static_cast<int>(largest.clique.size()) <= n) return {};
  return largest.clique;
}

std::vector<int> CompleteByMotion(const std::vector<MotionCandidate>& consensus,
                                  const std::vector<MotionCandidate>& candidates, int min_inliers,
                                  double threshold_m) {
  if (consensus.empty()) return {};
  std::set<int> used_source, used_target;
  for (const MotionCandidate& m : consensus) {
    used_source.insert(m.source);
    used_target.insert(m.target);
  }
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    if (static_cast<int>(candidates[static_cast<size_t>(i)].motion.source.size()) >= min_inliers)
      order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const MotionCandidate& x = candidates[static_cast<size_t>(a)];
    const MotionCandidate& y = candidates[static_cast<size_t>(b)];
    if (x.motion.source.size() != y.motion.source.size())
      return x.motion.source.size() > y.motion.source.size();
    return std::tie(x.source, x.target) < std::tie(y.source, y.target);
  });
  std::vector<const MatchMotion*> members;
  for (const MotionCandidate& m : consensus) members.push_back(&m.motion);
  std::vector<int> joined;
  for (int i : order) {
    const MotionCandidate& c = candidates[static_cast<size_t>(i)];
    if (used_source.count(c.source) || used_target.count(c.target)) continue;
    const bool agrees = std::all_of(members.begin(), members.end(), [&](const MatchMotion* m) {
      return MotionsAgree(*m, c.motion, threshold_m);
    });
    if (!agrees) continue;
    joined.push_back(i);
    members.push_back(&c.motion);
    used_source.insert(c.source);
    used_target.insert(c.target);
  }
  return joined;
}

}  // namespace zeroreg
