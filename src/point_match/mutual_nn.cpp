#include "point_match/descriptor_matcher.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {

std::vector<DescriptorMatch> MutualNearestNeighbourMatcher::Match(const Eigen::MatrixXf& source,
                                                                  const Eigen::MatrixXf& target,
                                                                  int /*threads*/) const {
  std::vector<DescriptorMatch> matches;
  if (source.rows() == 0 || target.rows() == 0) return matches;
  const Eigen::MatrixXf similarity = source * target.transpose();  // Eq. 3
  // Best target per source row and best source per target column; ties go to the lower index.
  std::vector<Eigen::Index> best_target(source.rows()), best_source(target.rows());
  for (Eigen::Index i = 0; i < similarity.rows(); ++i) similarity.row(i).maxCoeff(&best_target[i]);
  for (Eigen::Index j = 0; j < similarity.cols(); ++j) similarity.col(j).maxCoeff(&best_source[j]);
  for (Eigen::Index i = 0; i < similarity.rows(); ++i) {
    const Eigen::Index j = best_target[i];
    const float s = similarity(i, j);
    if (best_source[j] == i && s >= min_cosine_) {
      matches.push_back({static_cast<int>(i), static_cast<int>(j), s});
    }
  }
  return matches;
}

std::unique_ptr<DescriptorMatcher> MakeDescriptorMatcher(const MatchConfig& config) {
  if (config.method == "mutual_nn") {
    return std::make_unique<MutualNearestNeighbourMatcher>(config.min_cosine);
  }
  if (config.method == "sinkhorn") return MakeSinkhornMatcher(config.sinkhorn);
  throw MakeInputError("match.method", "unknown matcher '" + config.method +
                                           "'; expected \"sinkhorn\" or \"mutual_nn\"");
}

}  // namespace zeroreg
