#include "pipeline/object_correspondences.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <tuple>

#include "estimate/depth_noise.hpp"
#include "estimate/max_clique.hpp"
#include "graph/scene_graph.hpp"
#include "object_match/graph_match.hpp"
#include "object_match/motion_agreement.hpp"
#include "objects/proposals.hpp"

namespace zeroreg {
namespace {

bool InsideMask(const cv::Mat& mask, const Eigen::Vector2f& pixel) {
  const int x = static_cast<int>(std::lround(pixel.x()));
  const int y = static_cast<int>(std::lround(pixel.y()));
  return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uchar>(y, x) != 0;
}

// Rows of `features` whose keypoint lies inside `mask`.
std::vector<int> KeypointsInside(const ImageFeatures& features, const cv::Mat& mask) {
  std::vector<int> rows;
  for (int i = 0; i < features.size(); ++i) {
    if (InsideMask(mask, features.keypoints[i])) rows.push_back(i);
  }
  return rows;
}

std::vector<cv::Point> LargestOutline(const cv::Mat& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  if (contours.empty()) return {};
  return *std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
}

std::vector<ObjectSummary> Summarise(const SceneObjects& scene) {
  std::vector<ObjectSummary> out;
  for (const SceneObject& object : scene.objects) {
    ObjectSummary s;
    s.label = object.label;
    s.score = object.score;
    s.centroid = object.centroid;
    s.num_points = static_cast<int>(object.points.size());
    s.points = object.points;
    for (int i : object.observations) {
      const ObjectObservation& o = scene.observations[i];
      s.views.push_back({o.view, o.detection.box, o.detection.score, LargestOutline(o.mask)});
    }
    out.push_back(std::move(s));
  }
  return out;
}

// A point match inside an object pair, keyed by (source view, source row, target view, target
// row) so that a keypoint pair found in two overlapping object pairs is given once.
struct KeyedCorrespondence {
  std::tuple<int, int, int, int> key;
  Correspondence correspondence;
};

// §3.4 inside one object pair: every view of the source object against every view of the target
// object (or view i with view i only, method.object_all_view_pairs false; a single-view scan has
// one pair either way). A fragment may see an object in some views only.
std::vector<KeyedCorrespondence> MatchInsideObjects(const PerceivedScan& s, const PerceivedScan& t,
                                                    int source_object, int target_object,
                                                    const DescriptorMatcher& matcher,
                                                    bool all_view_pairs) {
  std::vector<KeyedCorrespondence> out;
  for (int is : s.objects.objects[source_object].observations) {
    for (int it : t.objects.objects[target_object].observations) {
      const ObjectObservation& os = s.objects.observations[is];
      const ObjectObservation& ot = t.objects.observations[it];
      if (!all_view_pairs && os.view != ot.view) continue;
      const LiftedFeatures& fs = s.view_features[os.view];
      const LiftedFeatures& ft = t.view_features[ot.view];
      const std::vector<int>& rows_s = s.observation_rows[is];
      const std::vector<int>& rows_t = t.observation_rows[it];
      const ImageFeatures sub_s = fs.features.Subset(rows_s), sub_t = ft.features.Subset(rows_t);
      for (const DescriptorMatch& m : matcher.Match(sub_s.descriptors, sub_t.descriptors, 1)) {
        const int a = rows_s[m.source], b = rows_t[m.target];
        out.push_back({{os.view, a, ot.view, b},
                       {fs.points[a], ft.points[b], fs.features.keypoints[a],
                        ft.features.keypoints[b], os.view, ot.view, m.score}});
      }
    }
  }
  return out;
}

// The most of an object pair's point matches that one rigid motion explains: the clique
// estimator's inliers (length consistency needs no transform guess, and it is deterministic).
// Returns their number; `motion` gets those inliers.
int RigidSupport(const std::vector<KeyedCorrespondence>& matches, const RansacConfig& ransac,
                 MatchMotion* motion) {
  if (matches.size() < 3) return static_cast<int>(matches.size());
  std::vector<Eigen::Vector3d> source, target;
  std::vector<float> scores;
  for (const KeyedCorrespondence& m : matches) {
    source.push_back(m.correspondence.source);
    target.push_back(m.correspondence.target);
    scores.push_back(m.correspondence.score);
  }
  const RansacResult fit = EstimateRigidClique(source, target, scores, ransac);
  for (size_t i = 0; i < fit.is_inlier.size(); ++i) {
    if (!fit.is_inlier[i]) continue;
    motion->source.push_back(source[i]);
    motion->target.push_back(target[i]);
  }
  return fit.num_inliers;
}

}  // namespace

void SemanticMatrices(const std::vector<SceneObject>& source,
                      const std::vector<SceneObject>& target, bool use_clip,
                      Eigen::MatrixXd* semantics_source, Eigen::MatrixXd* semantics_target) {
  int clip_dim = 0;
  std::map<std::string, int> one_hot;  // labels without an embedding -> column
  for (const auto* objects : {&source, &target}) {
    for (const SceneObject& o : *objects) {
      if (use_clip && o.semantic.size() > 0) {
        clip_dim = static_cast<int>(o.semantic.size());
      } else {
        one_hot.emplace(o.label, 0);
      }
    }
  }
  int column = clip_dim;
  for (auto& [label, col] : one_hot) col = column++;
  auto fill = [&](const std::vector<SceneObject>& objects, Eigen::MatrixXd* m) {
    *m = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(objects.size()), std::max(column, 1));
    for (size_t r = 0; r < objects.size(); ++r) {
      const SceneObject& o = objects[r];
      if (use_clip && o.semantic.size() == clip_dim && clip_dim > 0) {
        m->row(static_cast<Eigen::Index>(r)).head(clip_dim) = o.semantic.normalized().transpose();
      } else {
        (*m)(static_cast<Eigen::Index>(r), one_hot.at(o.label)) = 1.0;
      }
    }
  };
  fill(source, semantics_source);
  fill(target, semantics_target);
}

ObjectCorrespondenceSource::ObjectCorrespondenceSource(const PipelineConfig& config,
                                                       const FeatureExtractor& extractor,
                                                       Detector& detector, Segmenter& segmenter,
                                                       TextEmbedder* embedder,
                                                       const DescriptorMatcher& matcher)
    : config_(config),
      extractor_(extractor),
      detector_(detector),
      segmenter_(segmenter),
      embedder_(embedder),
      matcher_(matcher) {}

PerceivedScan ObjectCorrespondenceSource::Perceive(const Scan& scan, StageTimer& timer) const {
  PerceivedScan out;
  for (size_t v = 0; v < scan.views.size(); ++v) {
    const View& view = scan.views[v];
    timer.Restart();
    // The view's depth noise, measured once for the two noise floors that use it: lifting's
    // depth-edge test and the segmenter's depth steps (docs/CONFIG.md, "Depth noise").
    const bool noise_needed =
        config_.lift.edge_noise_sigmas > 0 || config_.segmenter.depth_noise_sigmas > 0;
    const double depth_noise_at_1m_m =
        noise_needed ? MeasureDepthNoiseAt1m(view).value_or(0.0) : 0.0;
    const ViewLift lift = LiftForView(config_.lift, config_.depth, depth_noise_at_1m_m);
    out.view_features.push_back(ExtractLiftedFeatures(extractor_, view, lift));
    out.view_lifts.push_back(lift);
    timer.Mark("features");
    // Either detections segmented one by one (§3.2), or, without detection, class-agnostic
    // depth regions that come with their masks.
    std::vector<ObjectObservation> found;
    ViewMasks masks;  // kept for the view's SAM embedding, when the segmenter computes one
    if (config_.method.detection) {
      // The file backends key their files by this name's stem: the image file, when known.
      const std::string& image_name = view.color_file.empty() ? view.name : view.color_file;
      const std::vector<Detection> detections = detector_.Detect(view.color, image_name);
      timer.Mark("detect");
      // One call per view: SAM encodes the image once for all its boxes.
      masks = segmenter_.SegmentView(view.color, view.depth, detections, image_name,
                                     depth_noise_at_1m_m);
      for (size_t d = 0; d < detections.size(); ++d) {
        ObjectObservation o;
        o.detection = detections[d];
        o.mask = std::move(masks.masks[d]);
        found.push_back(std::move(o));
      }
      timer.Mark("segment");
      TopUpWithProposals(view, config_.objects, lift, &found);
      timer.Mark("detect");
    } else {
      for (Proposal& p : DepthProposals(view.depth)) {
        ObjectObservation o;
        o.detection = p.detection;
        o.mask = std::move(p.mask);
        o.semantic = ColourHistogram(view.color, o.mask);  // appearance instead of CLIP
        found.push_back(std::move(o));
      }
      timer.Mark("detect");
    }
    // Each object's appearance beside its label; the SAM embedding pooled over the mask
    // where the segmenter computed one (objects.appearance = auto or sam-embedding).
    std::optional<EmbeddingPooler> pooler;
    if (config_.objects.appearance != "colour" && !masks.embedding.empty()) {
      pooler.emplace(masks.embedding, view.color.size());
    }
    for (ObjectObservation& o : found) {
      o.view = static_cast<int>(v);
      o.points = LiftMask(view, o.mask, config_.objects, lift);
      if (static_cast<int>(o.points.size()) < config_.objects.min_points) continue;
      o.appearance = pooler ? pooler->Pool(o.mask) : ColourAppearance(view.color, o.mask);
      // A proposal has no class to look up (the embedder would warn that "object" is in no table).
      if (embedder_ != nullptr && o.semantic.size() == 0 && o.detection.label != kProposalLabel) {
        std::lock_guard<std::mutex> lock(embedder_mutex_);
        if (auto e = embedder_->Embed(o.detection.label)) o.semantic = e->cast<double>();
      }
      out.objects.observations.push_back(std::move(o));
    }
    timer.Mark("objects");
  }
  timer.Restart();
  out.objects.objects = AssociateObservations(out.objects.observations,
                                              static_cast<int>(scan.views.size()), config_.objects);
  // Which keypoints each observation's mask holds depends on this scan alone: found once here,
  // not once per object pair and per registration the scan is in.
  for (const ObjectObservation& o : out.objects.observations) {
    out.observation_rows.push_back(KeypointsInside(out.view_features[o.view].features, o.mask));
  }
  out.object_summaries = Summarise(out.objects);
  out.num_keypoints = CountKeypoints(out.view_features);
  timer.Mark("objects");
  return out;
}

CorrespondenceSet ObjectCorrespondenceSource::Find(
    const std::shared_ptr<const PerceivedScan>& perceived_s,
    const std::shared_ptr<const PerceivedScan>& perceived_t, StageTimer& timer) const {
  const PerceivedScan& s = *perceived_s;
  const PerceivedScan& t = *perceived_t;
  CorrespondenceSet result;
  const std::vector<SceneObject>& objects_s = s.objects.objects;
  const std::vector<SceneObject>& objects_t = t.objects.objects;

  struct PointSupport {
    std::vector<KeyedCorrespondence> matches;
    int support = -1;    // -1: not measured
    MatchMotion motion;  // the `support` matches one rigid motion explains
  };
  std::map<std::pair<int, int>, PointSupport> candidates;  // (source, target) object
  // An object pair's §3.4 matches, found once per pair; with_support also measures their point
  // support (once).
  const auto inside = [&](int source_object, int target_object,
                          bool with_support) -> PointSupport& {
    const auto [it, is_new] = candidates.try_emplace({source_object, target_object});
    PointSupport& p = it->second;
    if (is_new) {
      p.matches = MatchInsideObjects(s, t, source_object, target_object, matcher_,
                                     config_.method.object_all_view_pairs);
    }
    if (with_support && p.support < 0)
      p.support = RigidSupport(p.matches, config_.ransac, &p.motion);
    return p;
  };

  // §3.3: scene graphs (Eq. 1), node similarity C, quadratic assignment (Eq. 2), label filter.
  timer.Restart();
  std::vector<ObjectPair> pairs;
  if (!objects_s.empty() && !objects_t.empty()) {
    Eigen::MatrixXd sem_s, sem_t, centroids_s(objects_s.size(), 3),
        centroids_t(objects_t.size(), 3);
    SemanticMatrices(objects_s, objects_t,
                     !config_.method.detection || (config_.method.clip && embedder_ != nullptr),
                     &sem_s, &sem_t);
    for (size_t i = 0; i < objects_s.size(); ++i) centroids_s.row(i) = objects_s[i].centroid;
    for (size_t i = 0; i < objects_t.size(); ++i) centroids_t.row(i) = objects_t[i].centroid;
    const Eigen::MatrixXd W_p = BuildAffinityMatrix(centroids_s, sem_s, config_.scene_graph);
    const Eigen::MatrixXd W_q = BuildAffinityMatrix(centroids_t, sem_t, config_.scene_graph);
    Eigen::MatrixXd appearance, comparable;
    AppearanceCosines(objects_s, objects_t, &appearance, &comparable);
    const Eigen::MatrixXd C = NodeSimilarity(sem_s, sem_t, appearance, comparable,
                                             config_.object_match.appearance_weight);
    ObjectMatchConfig match_config = config_.object_match;
    if (!config_.method.scene_graph) match_config.solver = ObjectMatchSolver::kNodeOnly;
    std::vector<std::string> labels_s, labels_t;
    for (const SceneObject& o : objects_s) labels_s.push_back(o.label);
    for (const SceneObject& o : objects_t) labels_t.push_back(o.label);
    const MatchMask labels_agree = LabelCompatibilityMask(labels_s, labels_t);
    // Label-incompatible pairs are forbidden inside Eq. 2, not only dropped after it as the paper
    // does: otherwise the structural term often prefers a wrong matching on near-regular graphs.
    MatchMask allowed = labels_agree;
    // Point support: the label-compatible pairs whose surfaces do not match point to point are
    // not candidates of Eq. 2 (object_match.min_point_support). Their matches are kept for §3.4.
    if (config_.object_match.min_point_support > 0) {
      timer.Mark("object_match");
      if (allowed.size() == 0)
        allowed = MatchMask::Constant(labels_agree.rows(), labels_agree.cols(), true);
      for (Eigen::Index j = 0; j < allowed.rows(); ++j) {
        for (Eigen::Index k = 0; k < allowed.cols(); ++k) {
          if (!allowed(j, k) || !labels_agree(j, k)) continue;
          allowed(j, k) = inside(static_cast<int>(j), static_cast<int>(k), true).support >=
                          config_.object_match.min_point_support;
        }
      }
      timer.Mark("point_match");  // §3.4's matching, done here for every candidate pair
    }
    const ObjectMatchResult matched =
        MatchObjects(W_p, W_q, C, match_config, allowed, config_.seed);
    // Paper §3.3: drop matched pairs whose labels differ.
    pairs = DropLabelMismatches(matched.pairs, labels_s, labels_t);
    // Then the matches whose own motions disagree with the majority's (the scene moves as one).
    if (config_.object_match.motion_agreement) {
      // Each match's motion comes with its point support: measured before Eq. 2 for every
      // candidate when min_point_support is on, here for the chosen pairs otherwise.
      std::vector<MatchMotion> motions;
      for (const ObjectPair& pair : pairs) {
        motions.push_back(inside(pair.source, pair.target, true).motion);
      }
      // Twice the inlier threshold: one object's motion carries another's points with both
      // motions' errors (as the clique's length test allows twice the noise bound).
      const double agreement_m = 2 * config_.ransac.inlier_threshold_m;
      const std::vector<int> consensus = MatchesInConsensus(motions, agreement_m);
      if (!consensus.empty()) {
        std::vector<ObjectPair> kept;
        for (int i : consensus) kept.push_back(pairs[static_cast<size_t>(i)]);
        result.rejected_object_matches += static_cast<int>(pairs.size() - kept.size());
        pairs = std::move(kept);
      }
      // Then the object pairs Eq. 2 left out whose own motion moves with that consensus (two
      // chairs of one class given each other's partners: the motion agreement dropped the wrong
      // one, and its object goes to the partner its point matches move with).
      if (config_.object_match.complete_by_motion && !consensus.empty()) {
        std::vector<MotionCandidate> members, left_out;
        for (const ObjectPair& pair : pairs) {
          members.push_back(
              {pair.source, pair.target, inside(pair.source, pair.target, true).motion});
        }
        for (Eigen::Index j = 0; j < labels_agree.rows(); ++j) {
          for (Eigen::Index k = 0; k < labels_agree.cols(); ++k) {
            if (!labels_agree(j, k)) continue;
            const int source = static_cast<int>(j), target = static_cast<int>(k);
            left_out.push_back({source, target, inside(source, target, true).motion});
          }
        }
        // At least 4 inliers: three point matches fit some motion whatever they are.
        const int min_inliers = std::max(4, config_.object_match.min_point_support);
        for (int i : CompleteByMotion(members, left_out, min_inliers, agreement_m)) {
          const MotionCandidate& c = left_out[static_cast<size_t>(i)];
          pairs.push_back({c.source, c.target, C(c.source, c.target)});
        }
      }
    }
  }
  timer.Mark("object_match");

  if (!config_.method.point_level) {
    // Table 4 row (b): the matched objects' centroids are the only correspondences.
    for (const ObjectPair& pair : pairs) {
      result.correspondences.push_back({objects_s[pair.source].centroid,
                                        objects_t[pair.target].centroid, Eigen::Vector2f::Zero(),
                                        Eigen::Vector2f::Zero(), 0, 0,
                                        static_cast<float>(pair.node_similarity)});
      result.object_matches.push_back({pair.source, pair.target, pair.node_similarity, 1});
      result.object_match_points.emplace_back();  // centroids only: no point matches
    }
    result.path = PathSource::kObjectCentroids;
    return result;
  }

  // §3.4: point matches inside every matched pair (computed earlier for the candidates when point
  // support was measured). Masks may overlap, so a keypoint pair is given once.
  std::set<std::tuple<int, int, int, int>> seen;  // (source view, row, target view, row)
  for (const ObjectPair& pair : pairs) {
    ObjectMatchSummary summary{pair.source, pair.target, pair.node_similarity, 0};
    const PointSupport& found = inside(pair.source, pair.target, false);
    summary.point_support = found.support;
    MatchMotion points;
    for (const KeyedCorrespondence& c : found.matches) {
      points.source.push_back(c.correspondence.source);
      points.target.push_back(c.correspondence.target);
      if (!seen.emplace(c.key).second) continue;
      result.correspondences.push_back(c.correspondence);
      ++summary.num_correspondences;
    }
    result.object_matches.push_back(summary);
    result.object_match_points.push_back(std::move(points));
  }
  result.path = PathSource::kObject;
  timer.Mark("point_match");

  const DescriptorMatcher& matcher = matcher_;
  const WholeImageViewPairs view_pairs = WholeImageViewPairsOf(config_.method);
  const int threads = config_.threads;
  result.whole_image_fallback = [perceived_s, perceived_t, &matcher, view_pairs, threads]() {
    std::vector<Correspondence> all;
    MatchWholeImages(perceived_s->view_features, perceived_t->view_features, matcher, view_pairs,
                     threads, &all);
    return all;
  };
  // Too little from the objects to even try: go to the whole images straight away.
  if (static_cast<int>(pairs.size()) < config_.method.min_object_matches ||
      static_cast<int>(result.correspondences.size()) < config_.method.min_object_correspondences) {
    result.correspondences = result.whole_image_fallback();
    result.whole_image_fallback = nullptr;
    result.path = PathSource::kImageFallback;
    timer.Mark("point_match");
  }
  return result;
}

}  // namespace zeroreg
