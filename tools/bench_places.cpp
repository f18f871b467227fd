// zeroreg-bench-places: keyframes and place recognition over the two recordings of each scene of
// ../shared/sessions (docs/RECORDINGS.md). Not installed; a benchmark, not a test.
//
//   zeroreg-bench-places [--data DIR] [--sessions FILE] [--scene NAME] [--threshold T]
//                        [--every K] [--words N] [--seed S] [--positive C] [--rerank N]
//                        [--min-cosine C] [--misses] [--keyframes-only]
//
// Per scene: keyframes of recording A and of recording B (src/recordings/keyframes.hpp; ground
// truth poses, or every K-th frame with --every), XFeat descriptors of each keyframe (the
// pipeline's default features: the extractor and config Pipeline::Prepare uses, keypoints with
// valid depth), a vocabulary of the scene's own keyframes' descriptors, and per B keyframe the A
// keyframes ranked by TF-IDF cosine (src/recordings/place_recognition.hpp). A B keyframe is a
// query when some A keyframe has ground-truth co-visibility >= C with it (the loop-closure
// protocol of ../shared/sessions/README.md, default 0.3); recall@K = the fraction of queries with
// such a keyframe among their K best-ranked. "chance@10" is the same for a random ranking
// (exact expectation), for scale, and chance@1. Prints one table; exits 2 on a bad argument or
// file.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "eval/sessions_protocol.hpp"
#include "features/feature_extractor.hpp"
#include "recordings/keyframes.hpp"
#include "recordings/place_recognition.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/config.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace {

using namespace zeroreg;

struct Keyframe {
  int frame = 0;
  View view;  // depth and intrinsics only (colour dropped after the features)
  Transform T_world_camera = Transform::Identity();
  Eigen::MatrixXf descriptors;
};

// Descriptors of the keypoints that have valid depth (what Prepare lifts and matches).
Eigen::MatrixXf DescriptorsWithDepth(const ImageFeatures& f, const View& view) {
  std::vector<int> keep;
  for (int i = 0; i < f.size(); ++i) {
    const int u = static_cast<int>(std::lround(f.keypoints[i].x()));
    const int v = static_cast<int>(std::lround(f.keypoints[i].y()));
    if (u < 0 || v < 0 || u >= view.depth.cols || v >= view.depth.rows) continue;
    const float d = view.depth.at<float>(v, u);
    if (std::isfinite(d) && d > 0.1f) keep.push_back(i);
  }
  Eigen::MatrixXf out(static_cast<Eigen::Index>(keep.size()), f.descriptors.cols());
  for (std::size_t r = 0; r < keep.size(); ++r) {
    out.row(static_cast<Eigen::Index>(r)) = f.descriptors.row(keep[r]);
  }
  return out;
}

std::vector<Keyframe> Keyframes(const Dataset& dataset, int first, int last,
                                const KeyframeConfig& config, bool use_poses,
                                const FeatureExtractor* extractor, int* frames, double* ms) {
  KeyframeSelector selector(config);
  std::vector<Keyframe> out;
  *frames = 0;
  for (int id : dataset.FrameIds()) {
    if (id < first || id > last) continue;
    ++*frames;
    View view = dataset.LoadFrame(id);
    if (!view.T_world_camera_gt) {
      throw InputError(dataset.root() + " frame " + std::to_string(id) +
                       ": no ground-truth pose (the benchmark's co-visibility needs it)");
    }
    const std::optional<Transform> pose =
        use_poses ? view.T_world_camera_gt : std::optional<Transform>();
    if (!selector.Add(view, pose)) continue;
    Keyframe k;
    k.frame = id;
    k.T_world_camera = *view.T_world_camera_gt;
    if (extractor) {
      const auto start = std::chrono::steady_clock::now();
      k.descriptors = DescriptorsWithDepth(extractor->Extract(view.color), view);
      *ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
    }
    k.view.name = view.name;
    k.view.depth = view.depth;
    k.view.intrinsics = view.intrinsics;
    out.push_back(std::move(k));
  }
  return out;
}

// Expected recall@k of a uniformly random ranking of n items of which p are right.
double Chance(int n, int p, int k) {
  if (p <= 0) return 0.0;
  double none = 1.0;  // probability that the first k hold no right item
  for (int i = 0; i < std::min(k, n); ++i) none *= static_cast<double>(n - p - i) / (n - i);
  return 1.0 - std::max(none, 0.0);
}

int Run(int argc, char** argv) {
  CLI::App app("Keyframes and place recognition over ../shared/sessions (docs/RECORDINGS.md)");
  std::string data = "../shared/data", sessions_file = "../shared/sessions/sessions.tsv", only;
  KeyframeConfig kf;
  VocabularyConfig vc;
  int every = 0;
  double positive = 0.3;
  bool keyframes_only = false, misses = false;
  int rerank = 0;
  float min_cosine = 0.8f;
  app.add_option("--data", data, "folder of the scenes");
  app.add_option("--sessions", sessions_file, "sessions list (scene, A range, B range)");
  app.add_option("--scene", only, "only this scene");
  app.add_option("--threshold", kf.covisibility_threshold, "keyframe co-visibility threshold");
  app.add_option("--every", every, "no poses: every K-th frame is a keyframe (fallback)");
  app.add_option("--words", vc.words, "vocabulary size");
  app.add_option("--seed", vc.seed, "k-means seed");
  app.add_option("--positive", positive, "co-visibility of a true loop-closure pair");
  app.add_option("--rerank", rerank, "re-rank the N best by mutual descriptor matches (0: off)");
  app.add_option("--min-cosine", min_cosine, "re-ranking: a match's minimum cosine");
  app.add_flag("--misses", misses, "print the queries missed at 10 to stderr");
  app.add_flag("--keyframes-only", keyframes_only, "count keyframes, no place recognition");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (every > 0) kf.fallback_every = every;
  ValidateKeyframeConfig(kf);
  ValidateVocabularyConfig(vc);
  if (!(positive > 0.0 && positive <= 1.0)) {
    throw InputError("--positive " + std::to_string(positive) + ": expected a fraction in (0, 1]");
  }

  const PipelineConfig pipeline;
  std::unique_ptr<FeatureExtractor> extractor;
  if (!keyframes_only) {
    extractor = MakeFeatureExtractor(pipeline.features, ResolveAssetsDir(pipeline.assets_dir),
                                     pipeline.inference);
  }
  std::printf(
      "keyframes: %s; vocabulary %d words, seed %llu; re-rank %d (cosine %.2f); "
      "positive: co-visibility >= %.2f\n",
      every > 0 ? ("every " + std::to_string(every) + " frames").c_str()
                : ("co-visibility < " + std::to_string(kf.covisibility_threshold)).c_str(),
      vc.words, static_cast<unsigned long long>(vc.seed), rerank, min_cosine, positive);
  std::printf(
      "| scene | frames A/B | keyframes A/B | queries | R@1 | R@5 | R@10 | chance@1 | chance@10 |"
      " XFeat ms/kf |\n|---|---|---|---|---|---|---|---|---|---|\n");
  int all_queries = 0;
  double all_hits[3] = {0, 0, 0};
  bool found = false;
  for (const SessionSplit& s : ReadSessionSplits(sessions_file)) {
    if (!only.empty() && s.scene != only) continue;
    found = true;
    const auto dataset = OpenDataset(data + "/" + s.scene);
    int frames_a = 0, frames_b = 0;
    double ms = 0.0;
    const std::vector<Keyframe> a =
        Keyframes(*dataset, s.a_first, s.a_last, kf, every == 0, extractor.get(), &frames_a, &ms);
    const std::vector<Keyframe> b =
        Keyframes(*dataset, s.b_first, s.b_last, kf, every == 0, extractor.get(), &frames_b, &ms);
    if (keyframes_only) {
      std::printf("| %s | %d/%d | %zu/%zu | | | | | | | |\n", s.scene.c_str(), frames_a, frames_b,
                  a.size(), b.size());
      std::fflush(stdout);
      continue;
    }
    std::vector<Eigen::MatrixXf> sets;
    for (const auto* rec : {&a, &b}) {
      for (const Keyframe& k : *rec) sets.push_back(k.descriptors);
    }
    PlaceIndex index(Vocabulary::Train(sets, vc));
    for (const Eigen::MatrixXf& d : sets) index.Add(d);
    index.Finalize();
    std::vector<int> database;
    for (std::size_t i = 0; i < a.size(); ++i) database.push_back(static_cast<int>(i));

    int queries = 0;
    double hits[3] = {0, 0, 0}, chance1 = 0.0, chance = 0.0;
    const int ks[3] = {1, 5, 10};
    for (std::size_t j = 0; j < b.size(); ++j) {
      std::vector<bool> right(a.size(), false);
      int positives = 0;
      double best_covisibility = 0.0;
      for (std::size_t i = 0; i < a.size(); ++i) {
        const double c =
            Covisibility(b[j].view, b[j].T_world_camera, a[i].view, a[i].T_world_camera, kf);
        right[i] = c >= positive;
        positives += right[i];
        best_covisibility = std::max(best_covisibility, c);
      }
      if (positives == 0) continue;
      ++queries;
      chance1 += Chance(static_cast<int>(a.size()), positives, 1);
      chance += Chance(static_cast<int>(a.size()), positives, 10);
      const int query = static_cast<int>(a.size() + j);
      std::vector<PlaceCandidate> ranked = index.Rank(query, database, -1);
      if (rerank > 0) {  // the first `rerank` re-ordered, the rest after them as they were
        const std::size_t n =
            std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(rerank));
        std::vector<PlaceCandidate> head(ranked.begin(), ranked.begin() + n);
        head = RerankByMatches(head, query, sets, min_cosine);
        std::copy(head.begin(), head.end(), ranked.begin());
      }
      for (int t = 0; t < 3; ++t) {
        for (int r = 0; r < ks[t] && r < static_cast<int>(ranked.size()); ++r) {
          if (right[static_cast<std::size_t>(ranked[static_cast<std::size_t>(r)].id)]) {
            hits[t] += 1;
            break;
          }
        }
      }
      if (misses) {
        std::size_t first = 0;
        while (first < ranked.size() && !right[static_cast<std::size_t>(ranked[first].id)]) {
          ++first;
        }
        if (first >= 10) {
          std::fprintf(stderr,
                       "miss: %s B frame %d: %d right of %zu A keyframes, best co-visibility "
                       "%.2f, first right at rank %zu\n",
                       s.scene.c_str(), b[j].frame, positives, a.size(), best_covisibility,
                       first + 1);
        }
      }
    }
    all_queries += queries;
    for (int t = 0; t < 3; ++t) all_hits[t] += hits[t];
    const auto pct = [&](double h) { return queries ? 100.0 * h / queries : 0.0; };
    std::printf("| %s | %d/%d | %zu/%zu | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %.0f |\n",
                s.scene.c_str(), frames_a, frames_b, a.size(), b.size(), queries, pct(hits[0]),
                pct(hits[1]), pct(hits[2]), pct(chance1), pct(chance),
                ms / std::max<std::size_t>(1, a.size() + b.size()));
    std::fflush(stdout);
  }
  if (!found) throw InputError("--scene " + only + ": not in " + sessions_file);
  if (!keyframes_only && all_queries > 0) {
    std::printf("| all | | | %d | %.1f | %.1f | %.1f | | | |\n", all_queries,
                100.0 * all_hits[0] / all_queries, 100.0 * all_hits[1] / all_queries,
                100.0 * all_hits[2] / all_queries);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const zeroreg::InputError& e) {
    std::cerr << "zeroreg-bench-places: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "zeroreg-bench-places: " << e.what() << "\n";
    return 1;
  }
}
