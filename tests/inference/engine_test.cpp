// inference.engine: ONNX Runtime and OpenCV DNN run the same models with the same pre-
// and post-processing, so XFeat keypoints/descriptors and YOLOX boxes must agree on real frames up
// to floating-point differences of the two engines' kernels; ONNX Runtime's output must not depend
// on its thread count; and the engine names are checked.
#include "inference/onnx_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "detect/backends.hpp"
#include "detect/perception_test_util.hpp"
#include "features/xfeat_extractor.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

using perception_test::AssetsDir;
using perception_test::ExpectInputError;
using perception_test::IoU;
using perception_test::ModelPaths;
using perception_test::ReadFrame;

// Frames of different content: table + chairs, the counter, a close-up (as in the SAM MANIFEST).
const int kFrames[] = {0, 500, 802};

InferenceConfig Engine(const std::string& name, int threads = 2) {
  InferenceConfig c;
  c.engine = name;
  c.threads = threads;
  return c;
}

std::string XFeatPath(const InferenceConfig& inference, const XFeatInput& input = {}) {
  return AssetsDir() + "/" + XFeatExtractor::ModelFile(inference, input);
}

TEST(InferenceEngine, ResolvesNamesAndRejectsBadOnes) {
  EXPECT_EQ(ResolveEngine(Engine("opencv")), InferenceEngine::kOpenCv);
  EXPECT_EQ(ResolveEngine(Engine("auto")),
            OnnxRuntimeAvailable() ? InferenceEngine::kOnnxRuntime : InferenceEngine::kOpenCv);
  ExpectInputError([] { ResolveEngine(Engine("tensorrt")); },
                   {"inference.engine", "tensorrt", "auto, onnxruntime, opencv"});
  ExpectInputError([] { ResolveEngine(Engine("auto", 0)); }, {"inference.threads", "1..256"});
  InferenceConfig no_cache = Engine("auto");
  no_cache.graph_cache = "";
  ExpectInputError([&] { ResolveEngine(no_cache); },
                   {"inference.graph_cache", "\"auto\", \"off\" or a directory"});
  if (OnnxRuntimeAvailable()) {
    EXPECT_EQ(ResolveEngine(Engine("onnxruntime")), InferenceEngine::kOnnxRuntime);
  } else {
    ExpectInputError([] { ResolveEngine(Engine("onnxruntime")); },
                     {"inference.engine", "built without ONNX Runtime", "opencv"});
  }
}

TEST(InferenceEngine, MissingModelFileIsNamed) {
  const std::string missing = AssetsDir() + "/no-such-model.onnx";
  ExpectInputError([&] { LoadOnnxModel(missing, "test model", Engine("opencv")); },
                   {missing, "cannot open the test model"});
}

// Each keypoint of `a` should have one of `b` within 0.5 px, with nearly the same descriptor
// and score. Returns the fraction that do; the worst cosine and score gap of those are reported.
struct Agreement {
  double matched_fraction = 0.0;
  double min_cosine = 1.0;
  double max_score_gap = 0.0;
};
Agreement Compare(const ImageFeatures& a, const ImageFeatures& b) {
  Agreement out;
  int matched = 0;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    int best = -1;
    double best_d2 = 0.25;  // (0.5 px)^2
    for (size_t j = 0; j < b.keypoints.size(); ++j) {
      const double dx = a.keypoints[i].x() - b.keypoints[j].x();
      const double dy = a.keypoints[i].y() - b.keypoints[j].y();
      if (dx * dx + dy * dy <= best_d2) {
        best_d2 = dx * dx + dy * dy;
        best = static_cast<int>(j);
      }
    }
    if (best < 0) continue;
    ++matched;
    const double cosine = a.descriptors.row(static_cast<Eigen::Index>(i))
                              .cast<double>()
                              .dot(b.descriptors.row(best).cast<double>());
    out.min_cosine = std::min(out.min_cosine, cosine);
    out.max_score_gap =
        std::max(out.max_score_gap, static_cast<double>(std::abs(a.scores[i] - b.scores[best])));
  }
  out.matched_fraction =
      a.keypoints.empty() ? 1.0 : static_cast<double>(matched) / a.keypoints.size();
  return out;
}

TEST(InferenceEngine, XFeatSameOnBothEngines) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  // OpenCV DNN runs the square export only, so both engines get the same 640x640 input here.
  const FeatureConfig config;
  XFeatInput square;
  square.square = true;
  const XFeatExtractor cv_dnn(XFeatPath(Engine("opencv"), square), config, Engine("opencv"),
                              square);
  const XFeatExtractor ort(XFeatPath(Engine("onnxruntime"), square), config, Engine("onnxruntime"),
                           square);
  for (int frame : kFrames) {
    const cv::Mat img = ReadFrame(frame);
    const ImageFeatures a = cv_dnn.Extract(img), b = ort.Extract(img);
    ASSERT_GT(a.keypoints.size(), 1000u) << "frame " << frame;
    // The top-k cut and the detection threshold may flip a few borderline keypoints.
    EXPECT_NEAR(static_cast<double>(b.keypoints.size()), static_cast<double>(a.keypoints.size()),
                0.01 * a.keypoints.size())
        << "frame " << frame;
    for (const Agreement& g : {Compare(a, b), Compare(b, a)}) {
      EXPECT_GE(g.matched_fraction, 0.99) << "frame " << frame;
      EXPECT_GE(g.min_cosine, 0.999) << "frame " << frame;
      EXPECT_LE(g.max_score_gap, 1e-3) << "frame " << frame;
    }
  }
}

// Both detectors find the same boxes on every test frame: same labels, IoU >= 0.99, scores within
// 1e-3. Returns the number of boxes (of cv_dnn), or -1 after a failed size check.
int ExpectSameBoxesOnEveryFrame(Detector& cv_dnn, Detector& ort) {
  int boxes = 0;
  for (int frame : kFrames) {
    const cv::Mat img = ReadFrame(frame);
    const std::vector<Detection> a = cv_dnn.Detect(img, "a.jpg"), b = ort.Detect(img, "b.jpg");
    EXPECT_EQ(a.size(), b.size()) << "frame " << frame;
    if (a.size() != b.size()) return -1;
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].label, b[i].label) << "frame " << frame << " box " << i;
      EXPECT_GE(IoU(a[i].box, b[i].box), 0.99f) << "frame " << frame << " box " << i;
      EXPECT_NEAR(a[i].score, b[i].score, 1e-3) << "frame " << frame << " box " << i;
    }
    boxes += static_cast<int>(a.size());
  }
  return boxes;
}

TEST(InferenceEngine, YoloxSameOnBothEngines) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  const DetectorModelPaths paths = ModelPaths();
  YoloxDetector cv_dnn(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{}, Engine("opencv"));
  YoloxDetector ort(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{}, Engine("onnxruntime"));
  EXPECT_GE(ExpectSameBoxesOnEveryFrame(cv_dnn, ort), 6);  // frame 0 alone has 4 (detector_test)
}

// PicoDet: ONNX Runtime runs the verbatim export, OpenCV DNN the Clip-rewritten copy; both feed the
// same PicodetInput / PicodetDecode.
TEST(InferenceEngine, PicodetSameOnBothEngines) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  const DetectorModelPaths paths = ModelPaths();
  PicodetDetector cv_dnn(paths.picodet_onnx, paths.picodet_opencv_onnx, paths.picodet_classes,
                         DetectorConfig{}, Engine("opencv"));
  PicodetDetector ort(paths.picodet_onnx, paths.picodet_opencv_onnx, paths.picodet_classes,
                      DetectorConfig{}, Engine("onnxruntime"));
  EXPECT_GE(ExpectSameBoxesOnEveryFrame(cv_dnn, ort), 6);
}

// ONNX Runtime's CPU kernels split work across threads without changing any sum's order (and the
// session asks for deterministic compute): 1 and 2 threads give bit-identical outputs.
TEST(InferenceEngine, OnnxRuntimeOutputDoesNotDependOnThreads) {
  if (!OnnxRuntimeAvailable()) GTEST_SKIP() << "built without ONNX Runtime";
  const FeatureConfig config;  // the any-size model at the frames' own 640x480
  const std::string xfeat = XFeatPath(Engine("onnxruntime"));
  const XFeatExtractor one(xfeat, config, Engine("onnxruntime", 1));
  const XFeatExtractor two(xfeat, config, Engine("onnxruntime", 2));
  const XFeatExtractor four(xfeat, config, Engine("onnxruntime", 4));
  const DetectorModelPaths paths = ModelPaths();
  YoloxDetector det_one(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{},
                        Engine("onnxruntime", 1));
  YoloxDetector det_two(paths.yolox_onnx, paths.yolox_classes, DetectorConfig{},
                        Engine("onnxruntime", 2));
  for (int frame : kFrames) {
    const cv::Mat img = ReadFrame(frame);
    const ImageFeatures a = one.Extract(img);
    for (const ImageFeatures& b : {two.Extract(img), four.Extract(img), one.Extract(img)}) {
      ASSERT_EQ(a.keypoints.size(), b.keypoints.size()) << "frame " << frame;
      for (size_t i = 0; i < a.keypoints.size(); ++i) {
        ASSERT_EQ(a.keypoints[i], b.keypoints[i]) << "frame " << frame << " keypoint " << i;
        ASSERT_EQ(a.scores[i], b.scores[i]) << "frame " << frame << " keypoint " << i;
      }
      EXPECT_TRUE(a.descriptors == b.descriptors) << "frame " << frame;
    }
    const std::vector<Detection> da = det_one.Detect(img, "a.jpg"),
                                 db = det_two.Detect(img, "b.jpg");
    ASSERT_EQ(da.size(), db.size());
    for (size_t i = 0; i < da.size(); ++i) {
      EXPECT_EQ(da[i].box, db[i].box);
      EXPECT_EQ(da[i].score, db[i].score);
    }
  }
}

}  // namespace
}  // namespace zeroreg
