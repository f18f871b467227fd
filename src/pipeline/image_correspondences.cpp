#include "pipeline/image_correspondences.hpp"

#include <algorithm>
#include <utility>

#include "parallel/parallel_for.hpp"

namespace zeroreg {

LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const LiftConfig& lift) {
  const ImageFeatures all = extractor.Extract(view.color);
  // Keypoints without usable depth cannot give a 3D correspondence; dropping them before matching
  // also keeps them from stealing a mutual nearest neighbour from a usable keypoint.
  std::vector<int> keep;
  LiftedFeatures out;
  for (int i = 0; i < all.size(); ++i) {
    if (auto point = LiftPixel(view, all.keypoints[i], lift)) {
      keep.push_back(i);
      out.points.push_back(*point);
    }
  }
  out.features = all.Subset(keep);
  return out;
}

int CountKeypoints(const std::vector<LiftedFeatures>& views) {
  int n = 0;
  for (const LiftedFeatures& f : views) n += f.features.size();
  return n;
}

void MatchWholeImages(const std::vector<LiftedFeatures>& source,
                      const std::vector<LiftedFeatures>& target, const DescriptorMatcher& matcher,
                      bool all_view_pairs, int threads, std::vector<Correspondence>* out) {
  std::vector<std::pair<int, int>> view_pairs;
  for (size_t vs = 0; vs < source.size(); ++vs) {
    for (size_t vt = 0; vt < target.size(); ++vt) {
      if (all_view_pairs || vs == vt) view_pairs.emplace_back(vs, vt);
    }
  }
  // A fragment pair has 9 view pairs of a few thousand keypoints each: one Sinkhorn per pair is
  // most of its matching time (issue 13), so the pairs are shared among the threads. A frame pair
  // has one, and its matcher gets the threads instead.
  std::vector<std::vector<Correspondence>> per_pair(view_pairs.size());
  const int matcher_threads = view_pairs.size() == 1 ? threads : 1;
  ParallelFor(
      view_pairs.size(), threads,
      [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
          const auto [vs, vt] = view_pairs[k];
          const LiftedFeatures& a = source[static_cast<size_t>(vs)];
          const LiftedFeatures& b = target[static_cast<size_t>(vt)];
          for (const DescriptorMatch& m :
               matcher.Match(a.features.descriptors, b.features.descriptors, matcher_threads)) {
            per_pair[k].push_back({a.points[m.source], b.points[m.target],
                                   a.features.keypoints[m.source], b.features.keypoints[m.target],
                                   vs, vt, m.score});
          }
        }
      },
      /*min_per_thread=*/1);
  for (const std::vector<Correspondence>& matches : per_pair) {
    out->insert(out->end(), matches.begin(), matches.end());
  }
}

}  // namespace zeroreg
