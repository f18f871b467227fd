// Object-level correspondences, the heart of ZeroReg:
//   §3.2  detect objects in every view, segment them, embed their labels, lift the masks to 3D and
//         associate the views' observations into the objects of each scan;
//   §3.3  build a kNN scene graph per scan (Eq. 1) and match the objects by the quadratic
//         assignment of Eq. 2, then drop pairs whose labels differ;
//   §3.4  inside every matched object pair and every view pair (view i with view i), match the
//         features that fall inside the two masks (S = G_P G_Q^T, Eq. 3; dustbin, Eq. 4; Sinkhorn).
// When the objects give too little (config.method), the same features are matched over the whole
// image instead and the result records path = PathSource::kImageFallback.
#pragma once

#include <memory>
#include <mutex>

#include "detect/detector.hpp"
#include "features/feature_extractor.hpp"
#include "objects/scene_objects.hpp"
#include "pipeline/correspondence_source.hpp"
#include "point_match/descriptor_matcher.hpp"
#include "segment/segmenter.hpp"
#include "semantics/text_embedder.hpp"
#include "zeroreg/config.hpp"

namespace zeroreg {

class ObjectCorrespondenceSource : public CorrespondenceSource {
 public:
  // `embedder` may be null: labels are then compared by equality only (the "w/o CLIP" row).
  ObjectCorrespondenceSource(const PipelineConfig& config, const FeatureExtractor& extractor,
                             Detector& detector, Segmenter& segmenter, TextEmbedder* embedder,
                             const DescriptorMatcher& matcher);
  PathSource path() const override { return PathSource::kObject; }
  PerceivedScan Perceive(const Scan& scan, StageTimer& timer) const override;
  CorrespondenceSet Find(const std::shared_ptr<const PerceivedScan>& source,
                         const std::shared_ptr<const PerceivedScan>& target,
                         StageTimer& timer) const override;

 private:
  const PipelineConfig& config_;
  const FeatureExtractor& extractor_;
  Detector& detector_;
  Segmenter& segmenter_;
  TextEmbedder* embedder_;
  mutable std::mutex embedder_mutex_;  // TextEmbedder::Embed is not thread-safe (its warnings)
  const DescriptorMatcher& matcher_;
};

// Semantic feature matrices of both scans' objects, one row per object: the CLIP text embedding of
// the label when known (and use_clip), otherwise a one-hot code of the label over the labels that
// have no embedding, so that cos = 1 for equal labels and 0 otherwise (docs/PERCEPTION.md).
void SemanticMatrices(const std::vector<SceneObject>& source,
                      const std::vector<SceneObject>& target, bool use_clip,
                      Eigen::MatrixXd* semantics_source, Eigen::MatrixXd* semantics_target);

}  // namespace zeroreg
