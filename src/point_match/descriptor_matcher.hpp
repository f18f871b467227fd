// Matching two sets of L2-normalised descriptors (paper §3.4). The matcher is swappable: mutual
// nearest neighbours here, Sinkhorn with a dustbin (Eq. 4) as the paper's choice.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "zeroreg/config.hpp"

namespace zeroreg {

struct DescriptorMatch {
  int source = 0;      // row of the source descriptors
  int target = 0;      // row of the target descriptors
  float score = 0.0f;  // cosine similarity or match probability
};

class DescriptorMatcher {
 public:
  virtual ~DescriptorMatcher() = default;
  virtual std::string name() const = 0;
  // Rows are L2-normalised descriptors of equal dimension. Returns matches sorted by source row,
  // the same whatever `threads` (how many threads the matcher may use; whole images use two).
  virtual std::vector<DescriptorMatch> Match(const Eigen::MatrixXf& source,
                                             const Eigen::MatrixXf& target, int threads) const = 0;
};

// Mutual nearest neighbours on cosine similarity S = G_P G_Q^T (Eq. 3), keeping pairs whose
// similarity is at least min_cosine.
class MutualNearestNeighbourMatcher : public DescriptorMatcher {
 public:
  explicit MutualNearestNeighbourMatcher(double min_cosine) : min_cosine_(min_cosine) {}
  std::string name() const override { return "mutual_nn"; }
  std::vector<DescriptorMatch> Match(const Eigen::MatrixXf& source, const Eigen::MatrixXf& target,
                                     int threads) const override;

 private:
  double min_cosine_;
};

// Sinkhorn with a dustbin (Eq. 3-4), mutual best matches above a probability (sinkhorn.hpp).
std::unique_ptr<DescriptorMatcher> MakeSinkhornMatcher(const SinkhornConfig& config);

// Builds the matcher named by config.method; throws InputError for an unknown name.
std::unique_ptr<DescriptorMatcher> MakeDescriptorMatcher(const MatchConfig& config);

}  // namespace zeroreg
