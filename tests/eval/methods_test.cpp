// Which pipeline config each `zeroreg eval --method` runs with (src/eval/methods.hpp).
#include <gtest/gtest.h>

#include "eval/methods.hpp"

namespace zeroreg {
namespace {

// --method image is the whole-image feature path alone (paper Table 4 row (a)). With the extra
// hypotheses on, an invalid whole-image estimate of 3DMatch 10 -> 13 was replaced by the geometry
// hypothesis and the run stopped ("the pipeline used the 'geometry clique' path").
TEST(EvalMethods, ImageMethodIsTheWholeImagePathWithoutExtraHypotheses) {
  const PipelineConfig image = MethodPipelineConfig("image", PipelineConfig{});
  EXPECT_FALSE(image.method.object_level);
  EXPECT_FALSE(image.hypotheses.enabled);
  // Everything else is the caller's config.
  PipelineConfig custom;
  custom.refine.enabled = false;
  custom.seed = 7;
  const PipelineConfig image_custom = MethodPipelineConfig("image", custom);
  EXPECT_FALSE(image_custom.refine.enabled);
  EXPECT_EQ(image_custom.seed, 7u);
  // --method zeroreg is the config as given.
  const PipelineConfig zeroreg = MethodPipelineConfig("zeroreg", PipelineConfig{});
  EXPECT_TRUE(zeroreg.method.object_level);
  EXPECT_TRUE(zeroreg.hypotheses.enabled);
}

}  // namespace
}  // namespace zeroreg
