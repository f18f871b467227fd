// End-to-end registration on real 7-Scenes redkitchen frames (whole-image feature path) against
// the dataset's ground-truth poses.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "eval/metrics.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

Scan Frame(int id) { return LoadScan(testing::RedkitchenDir() + "@" + std::to_string(id)); }

Transform GroundTruth(const Scan& source, const Scan& target) {
  return target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
}

class RegisterRealPair : public ::testing::TestWithParam<int> {};

TEST_P(RegisterRealPair, WithinFiveDegreesAndTenCentimetres) {
  const int i = GetParam();
  const Scan source = Frame(i + 20), target = Frame(i);
  const RegistrationResult r = Register(source, target);
  const Transform gt = GroundTruth(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_TRUE(PathName(r.path) == "object" || PathName(r.path) == "image-fallback")
      << PathName(r.path);
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.10);
  EXPECT_GT(CorrespondenceInlierRatio(r.correspondences, gt), 0.3);
  // The kitchen has a table and chairs in every frame: YOLOX finds objects in both scans.
  EXPECT_FALSE(r.source_objects.empty());
  EXPECT_FALSE(r.target_objects.empty());
}

TEST_P(RegisterRealPair, WholeImagePathWithinFiveDegreesAndTenCentimetres) {
  const int i = GetParam();
  const Scan source = Frame(i + 20), target = Frame(i);
  PipelineConfig config;
  config.method.object_level = false;  // the paper's Table 4 row (a)
  const RegistrationResult r = Register(source, target, config);
  const Transform gt = GroundTruth(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(PathName(r.path), "image");
  EXPECT_TRUE(r.source_objects.empty());
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.10);
}

INSTANTIATE_TEST_SUITE_P(Redkitchen, RegisterRealPair, ::testing::Values(0, 400, 800));

TEST(RegisterReal, SiftBackendAlsoRegisters) {
  const Scan source = Frame(20), target = Frame(0);
  PipelineConfig config;
  config.features.backend = "sift";
  const RegistrationResult r = Register(source, target, config);
  const Transform gt = GroundTruth(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.10);
}

// A scan of two real frames far apart in time, in the camera frame of the first (like a fused
// fragment keeps several views).
Scan TwoViewScan(int first, int second) {
  Scan scan = Frame(first);
  const Scan other = Frame(second);
  View view = other.views[0];
  view.T_scan_camera = scan.T_world_scan_gt->inverse() * *other.T_world_scan_gt;
  scan.views.push_back(view);
  scan.name += "+" + other.name;
  return scan;
}

int CrossViewInliers(const RegistrationResult& r) {
  int n = 0;
  for (size_t i = 0; i < r.correspondences.size(); ++i) {
    if (r.is_inlier[i] && r.correspondences[i].view != r.correspondences[i].target_view) ++n;
  }
  return n;
}

// A valid result within 5 deg / 10 cm of the ground truth whose inliers mostly come from view
// pairs with different indices (the crossed two-view scans below).
void ExpectRightFromCrossedViews(const RegistrationResult& r, const Transform& gt) {
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0);
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.10);
  EXPECT_GT(CrossViewInliers(r), r.num_inliers / 2);
}

TEST(RegisterReal, WholeImageMatchingPairsDifferentViewsWhenOnlyTheyOverlap) {
  // Source views: frames 520 and 20; target views: frames 0 and 500. Only source view 1 with
  // target view 0, and source view 0 with target view 1, show the same part of the kitchen.
  const Scan source = TwoViewScan(520, 20), target = TwoViewScan(0, 500);
  const Transform gt = GroundTruth(source, target);
  PipelineConfig config;
  config.method.min_object_matches = 1000;  // force the whole-image fallback
  const RegistrationResult r = Register(source, target, config);
  EXPECT_EQ(PathName(r.path), "image-fallback");
  ExpectRightFromCrossedViews(r, gt);

  // The whole-image path of row (a) pairs the views the same way.
  PipelineConfig image_path;
  image_path.method.object_level = false;
  const RegistrationResult image = Register(source, target, image_path);
  EXPECT_EQ(PathName(image.path), "image");
  ExpectRightFromCrossedViews(image, gt);

  // The four view pairs are matched on two threads by default; one thread gives the same bits.
  PipelineConfig one_thread = config;
  one_thread.threads = 1;
  const RegistrationResult serial = Register(source, target, one_thread);
  ASSERT_EQ(serial.correspondences.size(), r.correspondences.size());
  for (size_t i = 0; i < r.correspondences.size(); ++i) {
    ASSERT_EQ(serial.correspondences[i].source, r.correspondences[i].source) << i;
    ASSERT_EQ(serial.correspondences[i].target, r.correspondences[i].target) << i;
    ASSERT_EQ(serial.correspondences[i].view, r.correspondences[i].view) << i;
  }
  EXPECT_TRUE((serial.T_target_source.array() == r.T_target_source.array()).all());

  config.method.whole_image_all_view_pairs = false;  // view i with view i only
  const RegistrationResult same = Register(source, target, config);
  for (const Correspondence& c : same.correspondences) ASSERT_EQ(c.view, c.target_view);
}

// The object level matches a matched object in every view that sees it, not
// only view i with view i. With the views crossed as above, the objects' correspondences (and the
// inliers) come from the crossed view pairs; with object_all_view_pairs off there are none there.
TEST(RegisterReal, ObjectLevelMatchesEveryViewPairThatSeesTheObject) {
  const Scan source = TwoViewScan(520, 20), target = TwoViewScan(0, 500);
  const Transform gt = GroundTruth(source, target);
  const RegistrationResult r = Register(source, target);
  ASSERT_EQ(PathName(r.path), "object") << r.reason;
  ExpectRightFromCrossedViews(r, gt);

  PipelineConfig same_view;
  same_view.method.object_all_view_pairs = false;
  const RegistrationResult same = Register(source, target, same_view);
  if (PathName(same.path) == "object") {
    for (const Correspondence& c : same.correspondences) ASSERT_EQ(c.view, c.target_view);
  }
}

// The frame as a sensor of `scale` times Kinect v1's resolution would see it: colour
// resampled, depth by nearest neighbour, intrinsics scaled about pixel centres (as
// tools/resize_scene.cpp does for scripts/bench-resolution.sh).
Scan Resized(Scan scan, double scale) {
  View& v = scan.views[0];
  const cv::Size size(static_cast<int>(v.color.cols * scale),
                      static_cast<int>(v.color.rows * scale));
  cv::Mat color, depth;
  cv::resize(v.color, color, size, 0, 0, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::resize(v.depth, depth, size, 0, 0, cv::INTER_NEAREST);
  v.color = color;
  v.depth = depth;
  Intrinsics& K = v.intrinsics;
  K.fx *= scale;
  K.fy *= scale;
  K.cx = (K.cx + 0.5) * scale - 0.5;
  K.cy = (K.cy + 0.5) * scale - 0.5;
  K.width = size.width;
  K.height = size.height;
  return scan;
}

// Two sensors of different resolutions (1280x960 and 320x240 against the 640x480 frames): every
// stage that samples pixels does so per view (the pixel grids follow each view's size), so the
// pair registers as well as the 640x480 one.
TEST(RegisterReal, ScansOfDifferentResolutionsRegister) {
  const Scan source = Frame(60), target = Frame(0);
  const Transform gt = GroundTruth(source, target);
  for (const auto& [s, t] : {std::pair<double, double>{2.0, 1.0}, {0.5, 2.0}}) {
    const RegistrationResult r = Register(Resized(source, s), Resized(target, t));
    EXPECT_TRUE(r.valid) << s << " " << t << ": " << r.reason;
    EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 2.0) << s << " " << t;
    EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.03) << s << " " << t;
  }
}

TEST(RegisterReal, SameInputAndSeedGiveTheSameOutputBitForBit) {
  const Scan source = Frame(120), target = Frame(100);
  const RegistrationResult a = Register(source, target);
  const RegistrationResult b = Pipeline(PipelineConfig()).Register(source, target);
  EXPECT_TRUE((a.T_target_source.array() == b.T_target_source.array()).all());
  EXPECT_EQ(a.num_correspondences, b.num_correspondences);
  EXPECT_EQ(a.is_inlier, b.is_inlier);
}

TEST(RegisterReal, UnrelatedImagesAreReportedAsFailureNotIdentity) {
  // The target's colour is replaced by noise: no image correspondence can be right, so without
  // the hypotheses (the paper's flow) the result is a failure.
  const Scan source = Frame(20);
  Scan target = Frame(0);
  cv::RNG rng(1);
  rng.fill(target.views[0].color, cv::RNG::UNIFORM, 0, 255);
  PipelineConfig images_only;
  images_only.hypotheses.enabled = false;
  const RegistrationResult r = Register(source, target, images_only);
  EXPECT_FALSE(r.valid);
  EXPECT_FALSE(r.reason.empty());

  // The depth is untouched, so the geometry hypothesis (FPFH on the clouds) can still
  // register the pair: whatever the default returns, valid means right.
  const RegistrationResult d = Register(source, target);
  if (d.valid) {
    EXPECT_EQ(PathName(d.path).rfind("geometry", 0), 0u) << PathName(d.path);
    const Transform gt = GroundTruth(source, target);
    EXPECT_LT(RotationErrorDeg(d.T_target_source, gt), 5.0);
    EXPECT_LT(TranslationErrorM(d.T_target_source, gt), 0.10);
  }
}

// This pair was reported VALID 15 cm off (none of its correspondences within 0.1 m of
// the true pose) by the count verdict. The scans contradict each other under every estimate the
// pipeline finds, so the geometric check must refuse it.
TEST(RegisterReal, ConfidentWrongPairOfIssue10IsInvalid) {
  const Scan source = Frame(430), target = Frame(280);
  const RegistrationResult r = Register(source, target);
  const Transform gt = *target.views[0].T_world_camera_gt;
  const Transform T_gt = gt.inverse() * *source.views[0].T_world_camera_gt;
  if (r.valid) {
    EXPECT_LT(TranslationErrorM(r.T_target_source, T_gt), 0.05) << r.reason;
  }
  EXPECT_FALSE(r.valid) << r.reason;
  EXPECT_TRUE(r.verification.ran);
  EXPECT_GT(r.verification.violation, VerifyConfig().max_violation) << r.reason;
  EXPECT_FALSE(r.candidates.empty());
}

// redkitchen-cross 471 -> 866 (about 45 deg apart): RANSAC's inliers sit on repeated cabinet
// fronts, 8 deg off, and the check refuses that estimate; ICP from it reaches the truth (the rule
// that lets it, on stand-in candidates: JudgeRules.IcpFromARefusedEstimateIsJudgedByTheCheckAlone).
TEST(RegisterReal, RepeatedCabinetFrontsAcrossTheKitchenAreRegisteredRight) {
  const Scan source = Frame(866), target = Frame(471);
  const RegistrationResult r = Register(source, target);
  const Transform gt = GroundTruth(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 5.0) << r.reason;
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.10) << r.reason;
}

// redkitchen-gap60 200 -> 260: RANSAC inside the matched objects lands 7.6 deg / 14 cm off and the
// check refuses it. The judge refines every candidate before the arbiter asks the next source, so
// it passes at the pose the fallback's refined estimate would reach and the object level carries
// the pair.
TEST(RegisterReal, RefusedObjectEstimateIsRefinedBeforeTheFallback) {
  const Scan source = Frame(260), target = Frame(200);
  const Transform gt = GroundTruth(source, target);
  const RegistrationResult r = Register(source, target);
  EXPECT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(PathName(r.path), "object") << r.reason;
  EXPECT_LT(RotationErrorDeg(r.T_target_source, gt), 2.0) << r.reason;
  EXPECT_LT(TranslationErrorM(r.T_target_source, gt), 0.05) << r.reason;
  ASSERT_FALSE(r.candidates.empty());
  EXPECT_EQ(r.candidates.front().name, "object ransac");
  EXPECT_FALSE(r.candidates.front().passed) << "the pair no longer tests a refused object estimate";
  for (const CandidateSummary& c : r.candidates) {
    EXPECT_EQ(c.name.rfind("image-fallback", 0), std::string::npos) << "the fallback was asked";
  }
}

// The verdict is the geometric check's: valid results carry a passed check, and the check of the
// demo pair finds the scans agreeing on most of their surface with no free-space violations.
TEST(RegisterReal, ValidMeansTheCheckPassed) {
  const RegistrationResult r = Register(Frame(20), Frame(0));
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_TRUE(r.verification.passed);
  EXPECT_GT(r.verification.overlap, 0.8);
  EXPECT_LT(r.verification.violation, 0.01);
  int chosen = 0;
  for (const CandidateSummary& c : r.candidates) chosen += c.chosen;
  EXPECT_GE(chosen, 1);
}

TEST(RegisterReal, BadScansRaiseInputErrorNamingTheProblem) {
  Scan source = Frame(20), target = Frame(0);
  Scan empty;
  empty.name = "nothing";
  try {
    Register(empty, target);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no views"), std::string::npos) << e.what();
  }
  cv::resize(source.views[0].color, source.views[0].color, cv::Size(320, 240));
  try {
    Register(source, target);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("320x240"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace zeroreg
