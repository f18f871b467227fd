// Place recognition over keyframes: which keyframes of one recording may show the same place as a
// keyframe of another (or of the same recording, far apart in time), so that only those pairs are
// registered. A bag of visual words over the keyframes' own local descriptors (XFeat, 64-d,
// L2-normalised, as Pipeline::Prepare extracts them):
//   - a vocabulary: k-means of the recordings' own descriptors (k-means++ seeding and Lloyd
//     iterations, deterministic for a seed; no training data),
//   - per keyframe the histogram of its descriptors' nearest words, weighted by TF-IDF
//     (term frequency x log(N / number of keyframes holding the word)), L2-normalised,
//   - similarity of two keyframes = the cosine of their weighted histograms,
// after Sivic and Zisserman, "Video Google" (ICCV 2003); written from the paper's description.
// Eigen only; single-threaded, so the same input and seed give the same output everywhere.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace zeroreg {

struct VocabularyConfig {
  int words = 256;              // k of k-means
  int iterations = 10;          // Lloyd iterations after seeding (stops early when stable)
  int max_descriptors = 40000;  // training sample, drawn evenly from all descriptors
  std::uint64_t seed = 0;
};

// Throws InputError naming the field when a value is out of range.
void ValidateVocabularyConfig(const VocabularyConfig& config);

class Vocabulary {
 public:
  Vocabulary() = default;
  // One word per row of `centers` (any dimension, at least one row).
  explicit Vocabulary(Eigen::MatrixXf centers);
  // k-means of the rows of all `descriptor_sets` (one matrix per keyframe, same column count).
  // Fewer distinct descriptors than config.words: as many words as there are descriptors.
  // Throws InputError when there are no descriptors or the dimensions differ.
  static Vocabulary Train(const std::vector<Eigen::MatrixXf>& descriptor_sets,
                          const VocabularyConfig& config = {});

  int size() const { return static_cast<int>(centers_.rows()); }
  int dimension() const { return static_cast<int>(centers_.cols()); }
  const Eigen::MatrixXf& centers() const { return centers_; }
  // The nearest word (Euclidean) of each row; ties go to the lower word index.
  std::vector<int> Quantize(const Eigen::MatrixXf& descriptors) const;

 private:
  Eigen::MatrixXf centers_;
  Eigen::VectorXf center_norms_;  // squared
};

// A scored candidate: keyframe `id` of the index, cosine similarity `score` in [0, 1].
struct PlaceCandidate {
  int id = 0;
  double score = 0.0;
};

// The keyframes' weighted word histograms. Add every keyframe first, then Finalize (computes the
// IDF over all added keyframes), then query.
class PlaceIndex {
 public:
  explicit PlaceIndex(Vocabulary vocabulary);
  // Returns the keyframe's id (0, 1, ... in the order added). Throws InputError when the
  // descriptors' dimension is not the vocabulary's.
  int Add(const Eigen::MatrixXf& descriptors);
  void Finalize();
  int size() const { return static_cast<int>(counts_.size()); }
  const Vocabulary& vocabulary() const { return vocabulary_; }

  // IDF of a word: log(N / n_w), n_w = keyframes holding it; 0 for a word no keyframe holds.
  double Idf(int word) const;
  // Cosine similarity of two keyframes' TF-IDF histograms (0 when either is empty).
  double Similarity(int a, int b) const;
  // The `k` most similar keyframes to `query` among `database` (ids), best first; equal scores
  // in increasing id order. `query` itself is skipped if listed.
  std::vector<PlaceCandidate> Rank(int query, const std::vector<int>& database, int k) const;

 private:
  void RequireFinal(const char* what) const;
  Vocabulary vocabulary_;
  std::vector<std::vector<std::pair<int, int>>> counts_;     // per keyframe: (word, count), sorted
  std::vector<std::vector<std::pair<int, float>>> weights_;  // per keyframe, L2-normalised
  std::vector<double> idf_;
  bool final_ = false;
};

// Re-ranking by the descriptors themselves: the number of mutual nearest neighbours (cosine of the
// rows, which are L2-normalised) between two keyframes' descriptors with cosine >= min_cosine.
// Word histograms lose where in descriptor space a word's members lie; two views of one place
// share many one-to-one matches, two similar-looking places few. Only the first max_rows rows of
// each are used (the extractor sorts them strongest first), which bounds the cost.
int MutualMatches(const Eigen::MatrixXf& a, const Eigen::MatrixXf& b, float min_cosine = 0.8f,
                  int max_rows = 1024);

// The `candidates` (best first, e.g. PlaceIndex::Rank's) re-ordered by MutualMatches with the
// query's descriptors, most matches first; equal counts keep their order. `descriptors` holds
// every keyframe's descriptors by id. The scores become the match counts.
std::vector<PlaceCandidate> RerankByMatches(const std::vector<PlaceCandidate>& candidates,
                                            int query,
                                            const std::vector<Eigen::MatrixXf>& descriptors,
                                            float min_cosine = 0.8f, int max_rows = 1024);

// Pairs of keyframes of one recording worth asking about: for each keyframe, the `k` most similar
// keyframes at least `min_separation` positions away in the recording (ids are positions) that
// share some weighted word with it (score > 0), each pair once (lower id first), in query order
// and best first per query.
std::vector<std::pair<int, int>> FarApartCandidates(const PlaceIndex& index, int min_separation,
                                                    int k);

// Each keyframe's descriptors together with those of the `neighbours` keyframes before and after
// it in its own recording (`sets` holds the recordings one after another, `recording_sizes`
// keyframes each). A place revisited from elsewhere shares more words with the few views around
// a keyframe than with the one view alone: consecutive keyframes see overlapping parts of a place
// from a little apart. neighbours = 0 returns `sets`. Throws InputError when the sizes
// do not add up to the sets.
std::vector<Eigen::MatrixXf> WithNeighbours(const std::vector<Eigen::MatrixXf>& sets,
                                            const std::vector<int>& recording_sizes,
                                            int neighbours);

}  // namespace zeroreg
