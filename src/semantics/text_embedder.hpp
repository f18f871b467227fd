// Semantic features of object labels (paper §3.2, "Semantic Feature Extraction"): the CLIP text
// embedding of each category label. The CLIP text encoder itself cannot run here (OpenCV DNN), so
// the default backend looks labels up in tables of precomputed CLIP ViT-B/32 embeddings.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg {

class TextEmbedder {
 public:
  virtual ~TextEmbedder() = default;
  virtual std::string name() const = 0;
  // L2-normalised embedding of `label`, or nullopt when the label is unknown (the pipeline then
  // compares that label by equality).
  virtual std::optional<Eigen::VectorXf> Embed(const std::string& label) = 0;
};

// One table of a vocabulary: embeddings (.npy, float16, N x 512, from Detic) and its row names.
struct ClipTableFiles {
  std::string name;          // "coco", "objects365", "openimages", "lvis"
  std::string embeddings;    // path of the .npy
  std::string names;         // path of the names file (.txt: one per line; .csv: id,name,fixed)
  bool underscores = false;  // LVIS names were embedded with '_' for ' ' ("traffic_light")
};

// Looks a label up, case-insensitively, in the tables in the given order; the first table that
// has it wins. Unknown labels print a one-line warning once per label (std::cerr).
class ClipTableEmbedder : public TextEmbedder {
 public:
  explicit ClipTableEmbedder(const std::vector<ClipTableFiles>& tables);
  std::string name() const override { return "clip-table"; }
  std::optional<Eigen::VectorXf> Embed(const std::string& label) override;
  int dimension() const { return dimension_; }
  size_t vocabulary_size() const { return rows_.size(); }

 private:
  int dimension_ = 0;
  std::map<std::string, Eigen::VectorXf> rows_;  // lower-cased name -> normalised embedding
  std::set<std::string> warned_;
};

// Reads a NumPy .npy file of float16 or float32, C order, 2-D, into a float matrix. Throws
// InputError naming the file when the header or size is not what is expected.
Eigen::MatrixXf ReadNpyMatrix(const std::string& path);

// The four Detic tables inside the assets folder, in lookup order (COCO, Objects365, OpenImages,
// LVIS), each file verified against the repo's sha256 list.
std::vector<ClipTableFiles> DefaultClipTables(const std::string& assets_dir);

// Builds the embedder named by config.backend; throws InputError for an unknown name.
std::unique_ptr<TextEmbedder> MakeTextEmbedder(const SemanticsConfig& config,
                                               const std::string& assets_dir);

}  // namespace zeroreg
