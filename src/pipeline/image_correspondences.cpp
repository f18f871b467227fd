#include "pipeline/image_correspondences.hpp"

#include <algorithm>
#include <utility>

#include <opencv2/core.hpp>

#include "parallel/parallel_for.hpp"

namespace zeroreg {

namespace {

// Pixel (x, y) of the image turned clockwise by `quarter_turns` quarter turns, in the pixels of the
// unturned image (width w, height h; pixel centres at integers, as cv::rotate moves them).
Eigen::Vector2f UnturnPixel(const Eigen::Vector2f& p, int quarter_turns, int w, int h) {
  switch (quarter_turns) {
    case 1:  // ROTATE_90_CLOCKWISE: turned (x, y) shows unturned (y, h - 1 - x)
      return {p.y(), static_cast<float>(h - 1) - p.x()};
    case 2:  // ROTATE_180
      return {static_cast<float>(w - 1) - p.x(), static_cast<float>(h - 1) - p.y()};
    case 3:  // ROTATE_90_COUNTERCLOCKWISE: turned (x, y) shows unturned (w - 1 - y, x)
      return {static_cast<float>(w - 1) - p.y(), p.x()};
    default:
      return p;
  }
}

// The extractor's features of `bgr` turned clockwise by `quarter_turns` (any integer; taken
// modulo 4), with the keypoints in the pixels of `bgr` itself.
ImageFeatures ExtractTurned(const FeatureExtractor& extractor, const cv::Mat& bgr,
                            int quarter_turns) {
  const int turns = ((quarter_turns % 4) + 4) % 4;
  if (turns == 0) return extractor.Extract(bgr);
  static constexpr cv::RotateFlags kTurn[] = {cv::ROTATE_90_CLOCKWISE, cv::ROTATE_180,
                                              cv::ROTATE_90_COUNTERCLOCKWISE};
  cv::Mat turned;
  cv::rotate(bgr, turned, kTurn[turns - 1]);
  ImageFeatures features = extractor.Extract(turned);
  for (Eigen::Vector2f& k : features.keypoints) k = UnturnPixel(k, turns, bgr.cols, bgr.rows);
  return features;
}

}  // namespace

LiftedFeatures ExtractLiftedFeatures(const FeatureExtractor& extractor, const View& view,
                                     const ViewLift& lift, int quarter_turns) {
  const ImageFeatures all = ExtractTurned(extractor, view.color, quarter_turns);
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

WholeImageViewPairs WholeImageViewPairsOf(const MethodConfig& method) {
  return {method.whole_image_all_view_pairs, method.whole_image_max_view_pairs};
}

int CountKeypoints(const std::vector<LiftedFeatures>& views) {
  int n = 0;
  for (const LiftedFeatures& f : views) n += f.features.size();
  return n;
}

int ViewOverlapScore(const LiftedFeatures& a, const LiftedFeatures& b) {
  // Keypoints come strongest first (FeatureExtractor), so the heads are the strongest.
  const Eigen::Index n =
      std::min<Eigen::Index>(a.features.descriptors.rows(), kOverlapScoreKeypoints);
  const Eigen::Index m =
      std::min<Eigen::Index>(b.features.descriptors.rows(), kOverlapScoreKeypoints);
  if (n < 2 || m < 2) return 0;
  const Eigen::MatrixXf cosine =
      a.features.descriptors.topRows(n) * b.features.descriptors.topRows(m).transpose();
  std::vector<Eigen::Index> best_source(static_cast<size_t>(m));
  for (Eigen::Index j = 0; j < m; ++j) cosine.col(j).maxCoeff(&best_source[static_cast<size_t>(j)]);
  // Unit descriptors: squared distance 2 - 2 cos, so d1 < 0.8 d2 is 2 - 2 c1 < 0.64 (2 - 2 c2).
  constexpr float kRatio2 = 0.8f * 0.8f;
  int score = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    float best = -2.0f, second = -2.0f;
    Eigen::Index arg = 0;
    for (Eigen::Index j = 0; j < m; ++j) {
      const float c = cosine(i, j);
      if (c > best) {
        second = best;
        best = c;
        arg = j;
      } else if (c > second) {
        second = c;
      }
    }
    if (best_source[static_cast<size_t>(arg)] == i &&
        2.0f - 2.0f * best < kRatio2 * (2.0f - 2.0f * second)) {
      ++score;
    }
  }
  return score;
}

std::vector<std::pair<int, int>> ChooseViewPairs(const std::vector<LiftedFeatures>& source,
                                                 const std::vector<LiftedFeatures>& target,
                                                 const WholeImageViewPairs& choice, int threads) {
  std::vector<std::pair<int, int>> view_pairs;
  for (size_t vs = 0; vs < source.size(); ++vs) {
    for (size_t vt = 0; vt < target.size(); ++vt) {
      if (choice.all || vs == vt) view_pairs.emplace_back(vs, vt);
    }
  }
  const size_t max_pairs = choice.max_pairs == WholeImageViewPairs::kAsManyAsViews
                               ? std::max(source.size(), target.size())
                               : static_cast<size_t>(std::max(0, choice.max_pairs));
  if (max_pairs == 0 || view_pairs.size() <= max_pairs) return view_pairs;
  std::vector<int> score(view_pairs.size());
  ParallelFor(
      view_pairs.size(), threads,
      [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
          score[k] = ViewOverlapScore(source[static_cast<size_t>(view_pairs[k].first)],
                                      target[static_cast<size_t>(view_pairs[k].second)]);
        }
      },
      /*min_per_thread=*/1);
  std::vector<size_t> order(view_pairs.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t x, size_t y) { return score[x] > score[y]; });
  order.resize(max_pairs);
  std::sort(order.begin(), order.end());  // back to source-major order
  std::vector<std::pair<int, int>> chosen;
  for (size_t k : order) chosen.push_back(view_pairs[k]);
  return chosen;
}

void MatchWholeImages(const std::vector<LiftedFeatures>& source,
                      const std::vector<LiftedFeatures>& target, const DescriptorMatcher& matcher,
                      const WholeImageViewPairs& choice, int threads,
                      std::vector<Correspondence>* out) {
  const std::vector<std::pair<int, int>> view_pairs =
      ChooseViewPairs(source, target, choice, threads);
  // A fragment pair has 9 view pairs of a few thousand keypoints each: one Sinkhorn per pair is
  // most of its matching time, so the pairs are shared among the threads. A frame pair
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

namespace {

// Summed ViewOverlapScore over the view pairs `choice` allows (all, or view i with view i).
int SummedOverlapScore(const std::vector<LiftedFeatures>& source,
                       const std::vector<LiftedFeatures>& target,
                       const WholeImageViewPairs& choice) {
  int sum = 0;
  for (size_t vs = 0; vs < source.size(); ++vs) {
    for (size_t vt = 0; vt < target.size(); ++vt) {
      if (choice.all || vs == vt) sum += ViewOverlapScore(source[vs], target[vt]);
    }
  }
  return sum;
}

}  // namespace

TurnedFeatures ExtractTurnedFeatures(const FeatureExtractor& extractor, const Scan& scan,
                                     const std::vector<ViewLift>& lifts) {
  TurnedFeatures out;
  for (int q = 1; q <= 3; ++q) {
    for (size_t v = 0; v < scan.views.size(); ++v) {
      out[static_cast<size_t>(q - 1)].push_back(
          ExtractLiftedFeatures(extractor, scan.views[v], lifts[v], q));
    }
  }
  return out;
}

TurnedWholeImage MatchTurnedWholeImages(const TurnedFeatures& source_turned,
                                        const std::vector<LiftedFeatures>& source_features,
                                        const std::vector<LiftedFeatures>& target_features,
                                        const DescriptorMatcher& matcher,
                                        const WholeImageViewPairs& view_pairs, int min_score,
                                        int threads) {
  TurnedWholeImage out;
  out.overlap_scores[0] = SummedOverlapScore(source_features, target_features, view_pairs);
  for (size_t q = 1; q <= 3; ++q) {
    out.overlap_scores[q] = SummedOverlapScore(source_turned[q - 1], target_features, view_pairs);
  }
  for (int q = 1; q <= 3; ++q) {  // ties to the smaller turn
    if (out.overlap_scores[static_cast<size_t>(q)] >
        out.overlap_scores[static_cast<size_t>(out.quarter_turns)]) {
      out.quarter_turns = q;
    }
  }
  out.best_turn = out.quarter_turns;
  if (out.overlap_scores[static_cast<size_t>(out.quarter_turns)] < min_score) {
    out.quarter_turns = 0;
  }
  if (out.quarter_turns > 0) {
    MatchWholeImages(source_turned[static_cast<size_t>(out.quarter_turns - 1)], target_features,
                     matcher, view_pairs, threads, &out.correspondences);
  }
  return out;
}

}  // namespace zeroreg
