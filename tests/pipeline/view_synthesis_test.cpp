// View synthesis (hypotheses.view_synthesis) on real frames with ground truth: the target rendered
// into the source's true camera looks like the source's own depth; a revisit from across the
// room that no other source registers is registered right by matching the source's image against
// the target rendered from a refused estimate, and its picture shows the rendering.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "eval/metrics.hpp"
#include "synthesis/render.hpp"
#include "test_paths.hpp"
#include "viz/pictures.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

std::string HololensFrame(int id) {
  return testing::SharedDir() + "/data/hololens-office@" + std::to_string(id);
}

// hololens-office 33 <- 230 (hololens-low): 17 % co-visible, seen from across the room.
TEST(ViewSynthesis, TheTargetRenderedIntoTheSourcesTrueCameraShowsTheSourcesDepth) {
  const Scan source = LoadScan(HololensFrame(230));
  const Scan target = LoadScan(HololensFrame(33));
  const Transform gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
  const View& s = source.views[0];
  const RenderedView r = RenderScan(target, gt * s.T_scan_camera, s.intrinsics);
  std::vector<float> differences;
  for (int v = 0; v < r.depth.rows; ++v) {
    for (int u = 0; u < r.depth.cols; ++u) {
      const float rendered = r.depth.at<float>(v, u), seen = s.depth.at<float>(v, u);
      if (rendered > 0 && seen > 0) differences.push_back(std::abs(rendered - seen));
    }
  }
  ASSERT_GT(differences.size(), 5000u);
  std::nth_element(differences.begin(), differences.begin() + differences.size() / 2,
                   differences.end());
  // Where both see surface, mostly the same surface: the median within the sensors' noise and
  // the ground truth's error (a few centimetres at 2-4 m).
  EXPECT_LT(differences[differences.size() / 2], 0.06f);
}

TEST(ViewSynthesis, RegistersARevisitNoOtherSourceRegisters) {
  const Scan source = LoadScan(HololensFrame(230));
  const Scan target = LoadScan(HololensFrame(33));
  const Transform gt = target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
  const auto right = [&](const RegistrationResult& r) {
    return RotationErrorDeg(r.T_target_source, gt) < 3.0 &&
           TranslationErrorM(r.T_target_source, gt) < 0.08;
  };
  PipelineConfig without;
  without.hypotheses.view_synthesis = false;
  const RegistrationResult before = Register(source, target, without);
  EXPECT_FALSE(before.valid && right(before))
      << "the pair no longer tests the source: " << PathName(before.path) << ": " << before.reason;
  EXPECT_FALSE(before.valid && !right(before)) << PathName(before.path) << ": " << before.reason;

  const RegistrationResult after = Register(source, target, PipelineConfig());
  ASSERT_TRUE(after.valid) << after.reason;
  EXPECT_TRUE(right(after)) << RotationErrorDeg(after.T_target_source, gt) << " deg, "
                            << TranslationErrorM(after.T_target_source, gt) << " m";
  EXPECT_EQ(after.path.source, PathSource::kViewSynthesis) << PathName(after.path);
  ASSERT_TRUE(after.rendered_view.has_value());
  EXPECT_EQ(after.rendered_view->source_view, 0);
  const cv::Mat picture = DrawSynthesizedView(source, target, after);
  EXPECT_EQ(picture.cols, 2 * source.views[0].color.cols);
}

}  // namespace
}  // namespace zeroreg
