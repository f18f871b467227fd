// MotionPrior: a result is valid only within the prior's tolerance, and ICP from the prior is
// tried when no source gives a valid pose within it. Real pairs whose content is symmetric: the
// TUM cabinet seen from opposite sides, a long HoloLens table seen from both ends.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "eval/metrics.hpp"
#include "test_paths.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"
#include "zeroreg/register.hpp"

namespace zeroreg {
namespace {

Transform GroundTruth(const Scan& source, const Scan& target) {
  return target.T_world_scan_gt->inverse() * *source.T_world_scan_gt;
}

// The ground truth moved by 5 deg about the camera's x axis and 10 cm along its y axis: an
// odometry guess of the accuracy a loop-closure front end has.
Transform NearTruth(const Transform& gt) {
  Transform offset = Transform::Identity();
  offset.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(5.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  offset(1, 3) = 0.10;
  return gt * offset;
}

bool Right(const RegistrationResult& r, const Transform& gt) {
  return RotationErrorDeg(r.T_target_source, gt) < 15.0 &&
         TranslationErrorM(r.T_target_source, gt) < 0.30;
}

// tum-fr3-cabinet 39 <- 7 (co-visibility 20 %): an untextured box from opposite sides. The
// flipped pose puts faces, floor and colours together (overlap 64 %) and the check accepts it; at
// the truth the check sees 18 % of the surface in space the other camera saw through. With the
// prior the flip is not valid, and ICP from the prior is not valid either: invalid, not wrong.
TEST(MotionPrior, FlippedCabinetIsNotValidOutsideThePrior) {
  const std::string dir = testing::SharedDir() + "/data/tum-fr3-cabinet@";
  const Scan source = LoadScan(dir + "7");
  const Scan target = LoadScan(dir + "39");
  const Transform gt = GroundTruth(source, target);
  const Pipeline pipeline{PipelineConfig()};

  const RegistrationResult without = pipeline.Register(source, target);
  EXPECT_TRUE(without.valid && !Right(without, gt))
      << "the pair no longer tests the prior: " << without.path << ": " << without.reason;

  const RegistrationResult with = pipeline.Register(source, target, MotionPrior{NearTruth(gt)});
  EXPECT_FALSE(with.valid && !Right(with, gt)) << with.path << ": " << with.reason;
  EXPECT_NE(with.reason.find("from the motion prior (tolerance 15.0 deg, 30.0 cm)"),
            std::string::npos)
      << with.reason;
  EXPECT_NE(with.reason.find("[motion prior: ICP from it"), std::string::npos) << with.reason;
}

// hololens-office 124 <- 371 (co-visibility 21 %): a long table from its two ends. Without a
// prior the geometry source's half turn is valid and wrong; with one, ICP from the prior reaches
// the truth and the check accepts it.
TEST(MotionPrior, IcpFromThePriorRegistersTheSymmetricTable) {
  const std::string dir = testing::SharedDir() + "/data/hololens-office@";
  const Scan source = LoadScan(dir + "371");
  const Scan target = LoadScan(dir + "124");
  const Transform gt = GroundTruth(source, target);
  const Pipeline pipeline{PipelineConfig()};

  const RegistrationResult with = pipeline.Register(source, target, MotionPrior{NearTruth(gt)});
  ASSERT_TRUE(with.valid) << with.reason;
  EXPECT_EQ(with.path, "prior icp");
  EXPECT_LT(RotationErrorDeg(with.T_target_source, gt), 2.0);
  EXPECT_LT(TranslationErrorM(with.T_target_source, gt), 0.10);
  EXPECT_NE(with.reason.find("no source gave a valid pose within the motion prior"),
            std::string::npos)
      << with.reason;

  // Same input, same output, whatever the thread count.
  PipelineConfig one_thread;
  one_thread.threads = 1;
  const RegistrationResult serial =
      Pipeline(one_thread).Register(source, target, MotionPrior{NearTruth(gt)});
  EXPECT_EQ(serial.T_target_source, with.T_target_source);
  EXPECT_EQ(serial.path, with.path);
}

// A result inside the prior is the result without it, bit for bit.
TEST(MotionPrior, AResultWithinThePriorIsUnchanged) {
  const Scan source = LoadScan(testing::RedkitchenDir() + "@20");
  const Scan target = LoadScan(testing::RedkitchenDir() + "@0");
  const Pipeline pipeline{PipelineConfig()};
  const RegistrationResult without = pipeline.Register(source, target);
  const RegistrationResult with =
      pipeline.Register(source, target, MotionPrior{NearTruth(GroundTruth(source, target))});
  ASSERT_TRUE(without.valid) << without.reason;
  EXPECT_TRUE(with.valid) << with.reason;
  EXPECT_EQ(with.T_target_source, without.T_target_source);
  EXPECT_EQ(with.path, without.path);
  EXPECT_EQ(with.reason, without.reason);
}

TEST(MotionPrior, APriorThatIsNotRigidOrAToleranceThatIsNotPositiveIsRefusedByName) {
  const Scan source = LoadScan(testing::RedkitchenDir() + "@20");
  const Scan target = LoadScan(testing::RedkitchenDir() + "@0");
  PipelineConfig sift;
  sift.features.backend = "sift";
  sift.method.object_level = false;
  const Pipeline pipeline{sift};
  const auto message = [&](const MotionPrior& prior) {
    try {
      pipeline.Register(source, target, prior);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  MotionPrior scaled;
  scaled.T_target_source.topLeftCorner<3, 3>() *= 2.0;
  EXPECT_NE(message(scaled).find("motion prior T_target_source"), std::string::npos)
      << message(scaled);
  MotionPrior mirrored;
  mirrored.T_target_source(0, 0) = -1.0;
  EXPECT_NE(message(mirrored).find("not a rigid transform"), std::string::npos);
  MotionPrior nan_row;
  nan_row.T_target_source(3, 0) = std::nan("");
  EXPECT_NE(message(nan_row).find("motion prior T_target_source"), std::string::npos);
  MotionPrior no_tolerance;
  no_tolerance.max_translation_m = 0.0;
  EXPECT_NE(message(no_tolerance).find("motion prior tolerance"), std::string::npos)
      << message(no_tolerance);
  MotionPrior nan_tolerance;
  nan_tolerance.max_rotation_deg = std::nan("");
  EXPECT_NE(message(nan_tolerance).find("expected positive numbers"), std::string::npos);
}

}  // namespace
}  // namespace zeroreg
