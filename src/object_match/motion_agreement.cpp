#include "object_match/motion_agreement.hpp"

#include <numeric>

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
  const int n = static_cast<int>(motions.size());
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  if (n < 2) return all;
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
  if (2 * static_cast<int>(largest.clique.size()) <= n) return all;  // no strict majority
  return largest.clique;
}

}  // namespace zeroreg
