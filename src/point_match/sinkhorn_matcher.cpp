// DescriptorMatcher adapter for the Sinkhorn matcher of sinkhorn.hpp (paper §3.4, Eq. 3-4).
#include "point_match/descriptor_matcher.hpp"
#include "point_match/sinkhorn.hpp"

namespace zeroreg {
namespace {

class SinkhornMatcher : public DescriptorMatcher {
 public:
  explicit SinkhornMatcher(const SinkhornConfig& config) : config_(config) {}
  std::string name() const override { return "sinkhorn"; }
  std::vector<DescriptorMatch> Match(const Eigen::MatrixXf& source, const Eigen::MatrixXf& target,
                                     int threads) const override {
    std::vector<DescriptorMatch> out;
    for (const SinkhornMatch& m : MatchSinkhorn(source, target, config_, nullptr, threads)) {
      out.push_back({m.source, m.target, static_cast<float>(m.probability)});
    }
    return out;
  }

 private:
  SinkhornConfig config_;
};

}  // namespace

std::unique_ptr<DescriptorMatcher> MakeSinkhornMatcher(const SinkhornConfig& config) {
  return std::make_unique<SinkhornMatcher>(config);
}

}  // namespace zeroreg
